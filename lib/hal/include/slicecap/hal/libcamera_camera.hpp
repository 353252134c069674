// A camera through libcamera (Raspberry Pi camera modules): exposure, gain and white balance
// locked by controls, dmabuf planes mapped, frames with sensor timestamps and metadata.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/camera_error.hpp"

namespace libcamera {
class CameraConfiguration;
}

namespace slicecap::hal {

/// \brief The ids of the cameras libcamera finds, through the process's one CameraManager.
/// Throws CameraError if the manager cannot start.
std::vector<std::string> listLibcameraCameras();

/// \brief Every camera libcamera finds with its RAW formats and sensor modes (the Raw role's
/// formats and sizes) and its processed formats, for the hardware check. Needs no acquire.
/// Throws CameraError if the manager cannot start.
std::vector<CameraModes> listLibcameraModes();

/// \brief One libcamera camera, acquired for the object's lifetime. Every instance in a process
/// shares one libcamera::CameraManager (two alive at once abort the process); it is created with
/// the first camera and stopped with the last.
///
/// configure() asks for YUYV (else RGB/BGR888, XRGB8888, YUV420) at the requested size and
/// reports libcamera's Adjusted changes; exposure and gain, when set, are locked through
/// ExposureTime/AnalogueGain with AeEnable off; auto white balance is always off during capture.
/// Frames carry the sensor timestamp and the ExposureTime x (AnalogueGain x DigitalGain) the
/// request's metadata reports, and the start of row 0's exposure (SensorTimestamp -
/// ExposureTime) where both are reported.
///
/// RAW (CameraConfig::raw Auto or On): the camera's StreamRole::Raw stream alone, in a format
/// decodeBayer reads (the one libcamera proposes when it can, e.g. SRGGB10_CSI2P on a Pi 4's
/// IMX708), at the sensor mode whose 2 x 2 binned size best fits the request (chooseBayerSize:
/// 2304 x 1296 for 1280 x 720, delivered as 1152 x 648), decoded with each frame's
/// SensorBlackLevels (or kDefaultBlackLevel16, said once) into Linear16 frames; configure
/// reports the size and encoding it changed. A RAW format slicecap does not decode (the Pi 5's
/// PiSP compressed formats) is said once on stderr and in the ConfigResult, naming the camera
/// and the format, and Auto falls back to the processed stream (On is Invalid).
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
  /// Takes a RAW configuration the camera has applied: the delivered size and encoding.
  ConfigResult configureRaw(CameraConfig& config,
                            std::unique_ptr<libcamera::CameraConfiguration> configuration,
                            const BayerFormat& format);
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::hal
