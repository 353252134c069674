// The camera factory and the LED from their description (device_description.hpp).
#include "slicecap/rig/configured_devices.hpp"

#include <cmath>
#include <optional>
#include <variant>

#include "slicecap/hal/device_backends.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/hal/file_led.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/rig/rig_error.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig_scene.hpp"
#include "slicecap/vision/camera_scaling.hpp"

namespace slicecap::rig {
namespace {

namespace fs = std::filesystem;
using daemon::DaemonConfig;

// camera = model: the LED's light follows a switch this much later (a GPIO call and an LED
// driver take tens of microseconds).
constexpr std::int64_t kModelLedDelayUs = 40;

const std::pair<fs::path, io::Recording>& recordingFor(const RecordingsBySlice& recordings,
                                                       const fs::path& configured,
                                                       const SliceId& slice) {
  const auto found = recordings.find(slice);
  if (found == recordings.end())
    throw RigError(configured.string() + ": no recording of slice " + toString(slice));
  return found->second;
}

// The rig's scene frozen at its start: a person holding the target still under the camera.
class StillScene final : public hal::SceneSource {
 public:
  explicit StillScene(std::shared_ptr<hal::SceneSource> inner) : inner_(std::move(inner)) {}
  std::string id() const override { return inner_->id() + " (held still)"; }
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t) override {
    if (!light_) light_ = inner_->lightAt(0);
    return light_;
  }

 private:
  std::shared_ptr<hal::SceneSource> inner_;
  std::shared_ptr<const hal::SceneLight> light_;
};

}  // namespace

RecordingsBySlice findRecordings(const fs::path& configured) {
  RecordingsBySlice found;
  const auto add = [&found](const fs::path& directory) {
    io::Recording recording = io::readRecording(directory);
    if (recording.slice) found.try_emplace(recording.slice->id, directory, std::move(recording));
  };
  if (fs::exists(configured / io::kRecordingManifest)) {
    add(configured);
  } else {
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(configured, error))
      if (fs::exists(entry.path() / io::kRecordingManifest)) add(entry.path());
    if (error) throw RigError(configured.string() + ": " + error.message());
  }
  if (found.empty())
    throw RigError(configured.string() + ": no recording of a slice to play");
  return found;
}

namespace {

/// The frame size the camera last agreed to deliver (its configure's answer).
using DeliveredSize = std::optional<std::pair<int, int>>;

/// A camera that notes the size its configure settled on, for the camera model to follow.
class SizeNotingCamera : public hal::Camera {
 public:
  SizeNotingCamera(std::shared_ptr<hal::Camera> camera, std::shared_ptr<DeliveredSize> delivered)
      : camera_(std::move(camera)), delivered_(std::move(delivered)) {}
  std::string id() const override { return camera_->id(); }
  hal::ConfigResult configure(hal::CameraConfig& config) override {
    const int askedWidthPx = config.widthPx, askedHeightPx = config.heightPx;
    hal::ConfigResult result = camera_->configure(config);
    if (result.status == hal::ConfigResult::Status::Invalid) return result;
    // A binned RAW stream covers the sensor mode's field of view: the model scales to it. Another
    // aspect ratio is another crop, which no scaling of the calibration describes.
    const double aspectChange = (double(config.widthPx) / config.heightPx) /
                                (double(askedWidthPx) / askedHeightPx);
    if (!config.rawFormat.empty() && std::abs(aspectChange - 1.0) > 0.01)
      return {hal::ConfigResult::Status::Invalid,
              "its RAW stream " + config.rawFormat + " delivers " + std::to_string(config.widthPx) +
                  "x" + std::to_string(config.heightPx) + " frames for the " +
                  std::to_string(askedWidthPx) + "x" + std::to_string(askedHeightPx) +
                  " asked, another aspect ratio: set width and height to a size of the sensor's "
                  "aspect ratio, or camera_raw = off"};
    *delivered_ = std::pair{config.widthPx, config.heightPx};
    return result;
  }
  void start() override { camera_->start(); }
  void stop() override { camera_->stop(); }
  hal::CaptureResult nextFrame(std::chrono::milliseconds timeout) override {
    return camera_->nextFrame(timeout);
  }
  std::optional<int> readyDescriptor() const override { return camera_->readyDescriptor(); }
  hal::ExposureLock lockExposure(const hal::ExposureSetting& wanted) override {
    return camera_->lockExposure(wanted);
  }

 private:
  std::shared_ptr<hal::Camera> camera_;
  std::shared_ptr<DeliveredSize> delivered_;
};

// A camera may deliver another size than asked: a RAW stream 2 x 2 binned from its sensor mode
// (1152 x 648 from a camera module 3 asked for 1280 x 720; docs/real-sensors.md, RAW). The rig's
// camera model follows the size the camera last configured, so every pose, sample row and
// recording of the sweep is in the frames' own pixels.
void followDeliveredSize(CameraSources& sources) {
  auto delivered = std::make_shared<DeliveredSize>();
  sources.cameraFor = [inner = std::move(sources.cameraFor), delivered](const SliceId& slice) {
    return std::shared_ptr<hal::Camera>(std::make_shared<SizeNotingCamera>(inner(slice), delivered));
  };
  sources.rigFor = [inner = std::move(sources.rigFor), delivered](const SliceId& slice) {
    Rig rig = inner(slice);
    const vision::CameraIntrinsics& at = rig.camera.intrinsics;
    // Another crop than the calibration's is left as it is: the pipeline rejects the frames as
    // bad_frame naming both sizes, as before a camera could change its size.
    if (*delivered && (at.widthPx != (*delivered)->first || at.heightPx != (*delivered)->second) &&
        !vision::scalingProblem(rig.camera, (*delivered)->first, (*delivered)->second)) {
      rig.camera = rig.camera.scaledTo((*delivered)->first, (*delivered)->second);
    }
    return rig;
  };
}

// camera = model: a model camera per slice in front of the virtual rig.
void setModelCameras(CameraSources& sources, const ModelCameraDescription& model,
                     hal::Clock& clock, const std::shared_ptr<hal::LedTimeline>& modelLight,
                     const Rig& configured, ModelScene scene, bool modelRealTime) {
  // One renderer for every sweep (building it takes about half a second).
  auto renderer = std::make_shared<const sim::FrameRenderer>(
      configured.camera, configured.target, sim::loadMaterial(model.materialSpec), model.rig);
  hal::SensorModel sensor = model.sensor;
  if (scene == ModelScene::Still) sensor.holdSceneUntilStrobe = false;
  sensor.realTime = modelRealTime;
  sources.cameraFor = [renderer, rig = model.rig, sensor, modelLight, &clock,
                       scene](const SliceId& slice) {
    std::shared_ptr<hal::SceneSource> source = std::make_shared<sim::RigScene>(renderer, slice, rig);
    if (scene == ModelScene::Still) source = std::make_shared<StillScene>(std::move(source));
    return std::make_shared<hal::ModelCamera>(std::move(source), modelLight, clock, sensor);
  };
}

// camera = file: each slice's recording, played at its recorded rate, with its own rig.
void setFileCameras(CameraSources& sources, const FileCameraDescription& file, hal::Clock& clock) {
  auto recordings = std::make_shared<const RecordingsBySlice>(findRecordings(file.recording));
  const fs::path configured = file.recording;
  sources.firstSlice = recordings->begin()->first;
  sources.cameraFor = [recordings, configured, speed = file.speed, &clock](const SliceId& slice) {
    hal::FileCameraOptions options;
    options.paced = true;  // frames at their recorded rate (or `speed` x it), as a live camera delivers them
    options.speed = speed;
    return std::make_shared<hal::FileCamera>(recordingFor(*recordings, configured, slice).first,
                                             clock, options);
  };
  // A recording carries the camera and target it was taken with.
  sources.rigFor = [recordings, configured](const SliceId& slice) {
    const io::Recording& recording = recordingFor(*recordings, configured, slice).second;
    return Rig{recording.target, recording.camera};
  };
}

}  // namespace

CameraSources makeCameraSources(const DeviceDescription& devices, hal::Clock& clock,
                                std::shared_ptr<hal::LedTimeline> modelLight, ModelScene scene,
                                bool modelRealTime) {
  CameraSources sources;
  sources.firstSlice = SliceId{SliceKind::Diagonal, {30, 30}};
  // The three kinds exclude each other. They are taken in the order of the modules they reach
  // (lib/rig alone, sim's material, hal's devices), as the description's steps are.
  if (const auto* file = std::get_if<FileCameraDescription>(&devices.camera))
    setFileCameras(sources, *file, clock);
  if (const auto* model = std::get_if<ModelCameraDescription>(&devices.camera))
    setModelCameras(sources, *model, clock, modelLight, devices.rig, scene, modelRealTime);
  if (const auto* live = std::get_if<LiveCameraDescription>(&devices.camera)) {
    // One camera, whatever the slice. Through the factory: a build without the backend throws
    // BackendNotBuilt naming the option.
    std::shared_ptr<hal::Camera> camera = live->backend == hal::DeviceBackend::V4l2
                                              ? hal::openV4l2Camera(live->device)
                                              : hal::openLibcameraCamera(live->device);
    sources.cameraFor = [camera](const SliceId&) { return camera; };
  }
  if (!sources.rigFor)
    sources.rigFor = [configured = devices.rig](const SliceId&) { return configured; };
  followDeliveredSize(sources);
  return sources;
}

std::vector<std::string> backendsNotBuilt(const DaemonConfig& config) {
  std::vector<std::string> missing;
  const auto need = [&missing](const std::string& key, hal::DeviceBackend backend) {
    if (!hal::isBuilt(backend)) missing.push_back(key + ": " + hal::BackendNotBuilt(backend).what());
  };
  if (config.camera == DaemonConfig::CameraKind::Libcamera)
    need("camera = libcamera", hal::DeviceBackend::Libcamera);
  if (config.camera == DaemonConfig::CameraKind::V4l2) need("camera = v4l2", hal::DeviceBackend::V4l2);
  // The GPIO LED goes with the live cameras (openLed): file and model log to a file.
  if (config.camera == DaemonConfig::CameraKind::Libcamera ||
      config.camera == DaemonConfig::CameraKind::V4l2)
    need("the LED (led_chip, led_line)", hal::DeviceBackend::Gpiod);
  return missing;
}

std::unique_ptr<hal::Led> openLed(const LedDescription& led, hal::Clock& clock,
                                  std::shared_ptr<hal::LedTimeline> modelLight) {
  if (!led.log) return hal::openGpiodLed(led.gpio);
  fs::create_directories(led.log->parent_path());
  std::unique_ptr<hal::Led> fileLed = std::make_unique<hal::FileLed>(*led.log, clock);
  // camera = model: the model camera sees the light itself, a little after each switch (the
  // GPIO call and the LED driver), on its own timeline.
  if (led.seenByModel && modelLight)
    fileLed = std::make_unique<hal::TimelineLed>(std::move(fileLed), clock, modelLight,
                                                 kModelLedDelayUs);
  return fileLed;
}

}  // namespace slicecap::rig
