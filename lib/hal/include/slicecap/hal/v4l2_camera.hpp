// A V4L2 camera (USB cameras, /dev/videoN) with mmap streaming and, where the device offers it,
// manual exposure, gain and white balance.
#pragma once

#include <filesystem>
#include <memory>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/camera_error.hpp"

namespace slicecap::hal {

/// \brief Uncompressed formats only (YUYV, RGB24, BGR24, GREY; Y16 when linear16 is asked for):
/// a measurement cannot go through JPEG. Exposure is set through V4L2_CID_EXPOSURE_ABSOLUTE
/// (100 us units) with auto exposure off; gain through V4L2_CID_GAIN in the device's own units;
/// auto white balance is switched off when the device has it. What the device cannot do is
/// reported as ConfigResult::Adjusted with the reason.
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
