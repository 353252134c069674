// A V4L2 camera (USB cameras, /dev/videoN) with mmap streaming and, where the device offers it,
// manual exposure, gain and white balance.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/camera_error.hpp"
#include "slicecap/hal/raw_frame.hpp"

namespace slicecap::hal {

/// \brief What the V4L2 device at `devicePath` offers: its formats (RAW Bayer ones by libcamera's
/// names, e.g. SRGGB10_CSI2P, others by their fourcc) with their discrete frame sizes
/// (VIDIOC_ENUM_FMT, VIDIOC_ENUM_FRAMESIZES), for the hardware check. Throws CameraError naming
/// the path when it cannot be opened or is not a capture device.
CameraModes listV4l2Modes(const std::string& devicePath);

/// \brief The YUV decode a V4L2 format's colour fields ask for (v4l2_pix_format colorspace,
/// ycbcr_enc, quantization, as VIDIOC_S_FMT returns them): a DEFAULT encoding or quantization is
/// the colorspace's own (videodev2.h V4L2_MAP_YCBCR_ENC_DEFAULT and
/// V4L2_MAP_QUANTIZATION_DEFAULT: sRGB and SMPTE 170M are BT.601 limited, JPEG BT.601 full,
/// Rec.709 BT.709 limited). nullopt, with `why` saying which field, for a colorspace left at
/// DEFAULT (a driver that says nothing) or an encoding slicecap does not decode (BT.2020
/// constant luminance, SMPTE 240M, HSV).
std::optional<YuvEncoding> yuvEncodingOfV4l2(std::uint32_t colorspace, std::uint32_t ycbcrEncoding,
                                             std::uint32_t quantization, std::string* why);

/// \brief Uncompressed formats only (RGB24, BGR24, YUYV, YUV420, GREY; Y16 first when linear16
/// is asked for): a measurement cannot go through JPEG. RGB is taken before YUV; a YUV stream
/// is decoded by the colour space the driver reports (yuvEncodingOfV4l2), and refused (Invalid,
/// naming the device) when it reports none. Exposure is set through V4L2_CID_EXPOSURE_ABSOLUTE
/// (100 us units) with auto exposure off; gain through V4L2_CID_GAIN in the device's own units;
/// auto white balance is switched off when the device has it. What the device cannot do is
/// reported as ConfigResult::Adjusted with the reason.
///
/// RAW Bayer formats (10/12-bit CSI-2 packed or in 16-bit words, any CFA order; what a bridge
/// such as the Pi's unicam offers) are taken first unless CameraConfig::raw is Off (and only
/// they when On): the sensor mode twice the asked size, decoded by decodeBayer with the default
/// black level (V4L2 reports none) into Linear16 frames of half the mode's size.
///
/// Frames carry FrameMetadata::exposureStartUs from the buffer flags (v4l2ExposureStartUs): the
/// timestamp itself when it marks the start of exposure, minus CameraConfig::readoutUs and the
/// locked exposure when it marks the end of the frame, else nothing.
class V4l2Camera final : public Camera {
 public:
  /// \brief Opens the device. Throws CameraError naming it: missing, permission, not a V4L2
  /// capture device, or no streaming I/O.
  explicit V4l2Camera(const std::filesystem::path& device);
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  /// \brief "/dev/video0 (card name)".
  std::string id() const override;
  ConfigResult configure(CameraConfig& config) override;
  /// \brief Maps the buffers and starts streaming; CameraError naming the device if it refuses.
  void start() override;
  void stop() override;
  CaptureResult nextFrame(std::chrono::milliseconds timeout) override;
  std::optional<int> readyDescriptor() const override;
  ExposureLock lockExposure(const ExposureSetting& wanted) override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::hal
