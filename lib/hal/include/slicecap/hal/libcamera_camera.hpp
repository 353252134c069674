// A camera through libcamera (Raspberry Pi camera modules): exposure, gain and white balance
// locked by controls, dmabuf planes mapped, frames with sensor timestamps and metadata.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/camera_error.hpp"

namespace slicecap::hal {

/// \brief The ids of the cameras libcamera finds, through the process's one CameraManager.
/// Throws CameraError if the manager cannot start.
std::vector<std::string> listLibcameraCameras();

/// \brief One libcamera camera, acquired for the object's lifetime. Every instance in a process
/// shares one libcamera::CameraManager (two alive at once abort the process); it is created with
/// the first camera and stopped with the last.
///
/// configure() asks for YUYV (else RGB/BGR888, XRGB8888, YUV420) at the requested size and
/// reports libcamera's Adjusted changes; exposure and gain, when set, are locked through
/// ExposureTime/AnalogueGain with AeEnable off; auto white balance is always off during capture.
/// Frames carry the sensor timestamp and the ExposureTime x (AnalogueGain x DigitalGain) the
/// request's metadata reports.
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
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::hal
