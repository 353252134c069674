// A camera through libcamera (Raspberry Pi camera modules): exposure, gain and white balance
// locked by controls, dmabuf planes mapped, frames with sensor timestamps and metadata.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/camera_error.hpp"
#include "slicecap/hal/raw_frame.hpp"

namespace libcamera {
class CameraConfiguration;
class ColorSpace;
}

namespace slicecap::hal {

/// \brief The ids of the cameras libcamera finds, through the process's one CameraManager.
/// Throws CameraError if the manager cannot start.
std::vector<std::string> listLibcameraCameras();

/// \brief Every camera libcamera finds with its RAW formats and sensor modes (the Raw role's
/// formats and sizes), the RAW stream its validation grants for `wantedWidthPx` x
/// `wantedHeightPx` (CameraModes::validatedRaw, as configure negotiates it) and its processed
/// formats, for the hardware check. Needs no acquire. Throws CameraError if the manager cannot
/// start.
std::vector<CameraModes> listLibcameraModes(int wantedWidthPx, int wantedHeightPx);

/// \brief The YUV decode a libcamera stream's colour space (StreamConfiguration::colorSpace,
/// as validate() leaves it) asks for: its YcbcrEncoding (Rec601, Rec709, Rec2020) and Range.
/// nullopt for a colour space without a YCbCr encoding (YcbcrEncoding::None: RGB or RAW), which
/// says nothing of how a YUV stream is coded. ColorSpace::Sycc is Rec.601 full range, Smpte170m
/// Rec.601 limited, Rec709 Rec.709 limited (the Raspberry Pi's VideoRecording default).
std::optional<YuvEncoding> yuvEncodingOf(const libcamera::ColorSpace& colorSpace);

/// \brief One libcamera camera, acquired for the object's lifetime. Every instance in a process
/// shares one libcamera::CameraManager (two alive at once abort the process); it is created with
/// the first camera and stopped with the last.
///
/// configure() asks for an RGB format (BGR888, RGB888, XRGB8888; else YUYV, YUV420) at the
/// requested size and reports libcamera's Adjusted changes; a YUV stream is decoded by the
/// colour space validation leaves in it (yuvEncodingOf), and one without a colour space is
/// refused (Invalid, naming the camera and format) rather than decoded by a guess. Exposure
/// and gain, when set, are locked through ExposureTime/AnalogueGain with AeEnable off; during
/// capture auto white balance is off with unity ColourGains, Sharpness 0 and
/// NoiseReductionMode off where the camera has those controls (the ones it lacks are said once).
/// Frames carry the sensor timestamp and the ExposureTime x (AnalogueGain x DigitalGain) the
/// request's metadata reports, and the start of row 0's exposure (SensorTimestamp -
/// ExposureTime) where both are reported.
///
/// A pinned frame duration (CameraConfig::frameDurationUs, mains_hz) is sent as
/// FrameDurationLimits = {d, d} in the start controls and on every request, where the camera
/// lists the control, clamped into the range it lists after configure (planFrameDuration); the
/// duration granted is written back (nullopt where the camera lacks the control) and any change
/// said in the ConfigResult and once on stderr. An exposure longer than the frame, at configure
/// or in lockExposure, is clamped to it and said (clampExposureToFrame); a frame whose reported
/// FrameDuration is not the one pinned is said once.
///
/// RAW (CameraConfig::raw Auto or On): the camera's StreamRole::Raw stream alone, in a format
/// decodeBayer reads, negotiated through the camera's own validation (negotiateRawStream): the
/// one libcamera proposes when validation keeps it (SRGGB10_CSI2P on a Pi 4's IMX708), else its
/// unpacked twin (a Pi 5 replaces the packed request by its lossy RGGB_PISP_COMP1 and grants
/// SRGGB10 as SRGGB16), at the sensor mode whose 2 x 2 binned size best fits the request
/// (chooseBayerSize: 2304 x 1296 for 1280 x 720, delivered as 1152 x 648), decoded with each
/// frame's SensorBlackLevels (or kDefaultBlackLevel16, said once) into Linear16 frames;
/// configure reports the size and encoding it changed and what validation swapped. When
/// validation grants no format slicecap decodes, that is said once on stderr and in the
/// ConfigResult, naming the camera and each format asked for, and Auto falls back to the
/// processed stream (On is Invalid).
class LibcameraCamera final : public Camera {
 public:
  /// \brief Acquires the camera with this id, or the first one when `cameraId` is empty. Throws
  /// CameraError naming it: none found, no such id, or in use by another process.
  explicit LibcameraCamera(const std::string& cameraId);
  ~LibcameraCamera() override;
  LibcameraCamera(const LibcameraCamera&) = delete;
  LibcameraCamera& operator=(const LibcameraCamera&) = delete;

  std::string id() const override;
  ConfigResult configure(CameraConfig& config) override;
  /// \brief Allocates and maps buffers, starts the camera with the locked controls and queues
  /// every request; CameraError naming the camera if any step is refused.
  void start() override;
  void stop() override;
  CaptureResult nextFrame(std::chrono::milliseconds timeout) override;
  /// \brief An eventfd that is readable while completed frames wait.
  std::optional<int> readyDescriptor() const override;
  ExposureLock lockExposure(const ExposureSetting& wanted) override;

  struct State;

 private:
  /// The stream: RAW where negotiated, else the processed one (configure adds the frame
  /// duration after it).
  ConfigResult configureStream(CameraConfig& config);
  /// Takes a RAW configuration the camera has applied: the delivered size and encoding, said in
  /// `adjustments` after those given.
  ConfigResult configureRaw(CameraConfig& config,
                            std::unique_ptr<libcamera::CameraConfiguration> configuration,
                            const BayerFormat& format, std::vector<std::string> adjustments);
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::hal
