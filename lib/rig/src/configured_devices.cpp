// The camera factory and the LED from slicecapd's configuration.
#include "slicecap/rig/configured_devices.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/device_backends.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/hal/file_led.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/hal/room_flicker.hpp"
#include "slicecap/io/target_json.hpp"
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

// camera = model's sensor: the configured tone curve, RAW stream, seed, room light, Pi and ISP.
hal::SensorModel modelSensor(const DaemonConfig& config, ModelScene scene, bool modelRealTime) {
  hal::SensorModel sensor;
  sensor.seed = static_cast<std::uint64_t>(config.modelSeed);
  sensor.tone = config.modelToneCurve == "srgb"     ? ToneCurve::srgb()
                : config.modelToneCurve == "linear" ? ToneCurve::linear()
                                                    : ToneCurve::imx708Tuning();
  // model_raw: the model's sensor offers a RAW stream, taken as camera_raw says.
  if (!config.modelRaw.empty()) sensor.rawFormat = hal::bayerFormatFromLibcameraName(config.modelRaw);
  if (scene == ModelScene::Still) sensor.holdSceneUntilStrobe = false;
  sensor.flickerHz = config.modelFlickerHz;
  sensor.flickerDepth = config.modelFlickerDepth;
  sensor.pipeline = *hal::parseModelPipeline(config.modelPipeline);  // checked when read
  sensor.isp.adaptiveContrast = config.modelAdaptiveContrast;
  if (config.modelColourMatrix == "imx708") sensor.isp.colourMatrix = hal::kImx708ColourMatrix;
  if (config.modelStream == "rec709")
    sensor.isp.yuvStream = hal::YuvEncoding{hal::YcbcrMatrix::Rec709, hal::YuvRange::Limited};
  if (config.modelStream == "sycc")
    sensor.isp.yuvStream = hal::YuvEncoding{hal::YcbcrMatrix::Rec601, hal::YuvRange::Full};
  sensor.isp.temporalDenoiseWeight = config.modelTemporalDenoise;
  sensor.isp.timestampJitterUs = config.modelTimestampJitterUs;
  sensor.isp.locksCountedByRequest = config.modelLocksCountedByRequest;
  sensor.realTime = modelRealTime;
  return sensor;
}

// camera = model: a model camera per slice in front of the virtual rig.
void setModelCameras(CameraSources& sources, const DaemonConfig& config, hal::Clock& clock,
                     const std::shared_ptr<hal::LedTimeline>& modelLight,
                     const vision::TargetGeometry& target, const vision::CameraModel& cameraModel,
                     ModelScene scene, bool modelRealTime) {
  // One renderer for every sweep (building it takes about half a second).
  sim::RigParams rig = config.modelRealistic ? sim::RigParams::realistic() : sim::RigParams::ideal();
  rig.framesPerSlice = config.modelPositions;
  rig.sweepSeconds = config.modelSweepSeconds;
  rig.seed = static_cast<std::uint64_t>(config.modelSeed);
  // model_room_light: the room's irradiance against the LED's face-on at the rig's distance
  // (intensity / d^2, the rig's radiometry).
  const double lightDistanceM = rig.lightDistanceMm / 1000.0;
  rig.ambientIrradiance = config.modelRoomLight * rig.ledIntensityWPerSr / (lightDistanceM * lightDistanceM);
  auto renderer = std::make_shared<const sim::FrameRenderer>(
      cameraModel, target, sim::loadMaterial(config.modelMaterial), rig);
  const hal::SensorModel sensor = modelSensor(config, scene, modelRealTime);
  sources.cameraFor = [renderer, rig, sensor, modelLight, &clock, scene](const SliceId& slice) {
    std::shared_ptr<hal::SceneSource> source = std::make_shared<sim::RigScene>(renderer, slice, rig);
    if (scene == ModelScene::Still) source = std::make_shared<StillScene>(std::move(source));
    return std::make_shared<hal::ModelCamera>(std::move(source), modelLight, clock, sensor);
  };
  sources.kind = "model camera";
}

// camera = file: each slice's recording, played at its recorded rate, with its own rig.
void setFileCameras(CameraSources& sources, const DaemonConfig& config, hal::Clock& clock) {
  auto recordings = std::make_shared<const RecordingsBySlice>(findRecordings(config.recording));
  const fs::path configured = config.recording;
  sources.firstSlice = recordings->begin()->first;
  sources.cameraFor = [recordings, configured, &clock](const SliceId& slice) {
    hal::FileCameraOptions options;
    options.paced = true;  // frames at their recorded rate, as a live camera delivers them
    return std::make_shared<hal::FileCamera>(recordingFor(*recordings, configured, slice).first,
                                             clock, options);
  };
  // A recording carries the camera and target it was taken with.
  sources.rigFor = [recordings, configured](const SliceId& slice) {
    const io::Recording& recording = recordingFor(*recordings, configured, slice).second;
    return Rig{recording.target, recording.camera};
  };
  sources.kind = "file camera";
}

}  // namespace

Rig configuredRig(const DaemonConfig& config) {
  Rig rig{config.target == "default" ? vision::defaultTarget() : io::readTargetJson(config.target),
          vision::defaultSimulatedCamera()};
  if (!config.calibration.empty())
    rig.camera =
        io::cameraFromJson(io::readJsonFile(config.calibration), config.calibration.string(), "");
  return rig;
}

hal::CameraConfig cameraConfigFrom(const DaemonConfig& config) {
  hal::CameraConfig camera;
  camera.widthPx = config.widthPx;
  camera.heightPx = config.heightPx;
  camera.exposureUs = config.exposureUs;
  camera.gain = config.gain;
  camera.raw = config.cameraRaw;
  camera.readoutUs = config.readoutUs;
  camera.frameDurationUs = hal::frameDurationUsForMains(config.mainsHz);
  camera.mainsHz = config.mainsHz;
  return camera;
}

CameraSources makeCameraSources(const DaemonConfig& config, hal::Clock& clock,
                                std::shared_ptr<hal::LedTimeline> modelLight,
                                const vision::TargetGeometry& target,
                                const vision::CameraModel& cameraModel, ModelScene scene,
                                bool modelRealTime) {
  CameraSources sources;
  sources.firstSlice = SliceId{SliceKind::Diagonal, {30, 30}};
  switch (config.camera) {
    case DaemonConfig::CameraKind::Libcamera: {
      // Through the factory: a build without libcamera throws BackendNotBuilt naming the option.
      std::shared_ptr<hal::Camera> camera = hal::openLibcameraCamera(config.cameraDevice);
      sources.cameraFor = [camera](const SliceId&) { return camera; };
      sources.kind = "libcamera";
      break;
    }
    case DaemonConfig::CameraKind::V4l2: {
      std::shared_ptr<hal::Camera> camera = hal::openV4l2Camera(
          config.cameraDevice.empty() ? std::string("/dev/video0") : config.cameraDevice);
      sources.cameraFor = [camera](const SliceId&) { return camera; };
      sources.kind = "v4l2";
      break;
    }
    case DaemonConfig::CameraKind::Model:
      setModelCameras(sources, config, clock, modelLight, target, cameraModel, scene,
                      modelRealTime);
      break;
    case DaemonConfig::CameraKind::File:
      setFileCameras(sources, config, clock);
      break;
  }
  if (!sources.rigFor) sources.rigFor = [=](const SliceId&) { return Rig{target, cameraModel}; };
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

std::unique_ptr<hal::Led> openLed(const DaemonConfig& config, hal::Clock& clock,
                                  std::shared_ptr<hal::LedTimeline> modelLight) {
  if (config.camera == DaemonConfig::CameraKind::File ||
      config.camera == DaemonConfig::CameraKind::Model) {
    const fs::path log = config.ledLog.empty() ? config.storage / "led.log" : config.ledLog;
    fs::create_directories(log.parent_path());
    std::unique_ptr<hal::Led> led = std::make_unique<hal::FileLed>(log, clock);
    // camera = model: the model camera sees the light itself, a little after each switch (the
    // GPIO call and the LED driver), on its own timeline.
    if (config.camera == DaemonConfig::CameraKind::Model && modelLight)
      led = std::make_unique<hal::TimelineLed>(std::move(led), clock, modelLight, kModelLedDelayUs);
    return led;
  }
  return hal::openGpiodLed(hal::GpioLineSpec{config.ledChip, config.ledLine, config.ledActiveLow});
}

}  // namespace slicecap::rig
