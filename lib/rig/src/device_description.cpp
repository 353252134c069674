// slicecapd.conf's device keys to a DeviceDescription: every name and value parsed here, once.
#include "slicecap/rig/device_description.hpp"

#include <cstdint>
#include <string>
#include <tuple>
#include <utility>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/model_isp.hpp"
#include "slicecap/hal/room_flicker.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/sim/room_light.hpp"

namespace slicecap::rig {
namespace {

using daemon::DaemonConfig;

// camera = model's sensor: the configured tone curve, seed, room light and ISP (its RAW
// stream and Pi are names, parsed in describeDevices).
hal::SensorModel modelSensor(const DaemonConfig& config) {
  hal::SensorModel sensor;
  sensor.seed = static_cast<std::uint64_t>(config.modelSeed);
  sensor.tone = config.modelToneCurve == "srgb"     ? ToneCurve::srgb()
                : config.modelToneCurve == "linear" ? ToneCurve::linear()
                                                    : ToneCurve::imx708Tuning();
  sensor.flickerHz = config.modelFlickerHz;
  sensor.flickerDepth = config.modelFlickerDepth;
  sensor.isp.adaptiveContrast = config.modelAdaptiveContrast;
  if (config.modelColourMatrix == "imx708") sensor.isp.colourMatrix = hal::kImx708ColourMatrix;
  if (config.modelStream == "rec709")
    sensor.isp.yuvStream = hal::YuvEncoding{hal::YcbcrMatrix::Rec709, hal::YuvRange::Limited};
  if (config.modelStream == "sycc")
    sensor.isp.yuvStream = hal::YuvEncoding{hal::YcbcrMatrix::Rec601, hal::YuvRange::Full};
  sensor.isp.temporalDenoiseWeight = config.modelTemporalDenoise;
  sensor.isp.timestampJitterUs = config.modelTimestampJitterUs;
  sensor.isp.locksCountedByRequest = config.modelLocksCountedByRequest;
  return sensor;
}

// camera = model: the virtual rig as configured (its room light is worked out from it in
// describeDevices).
sim::RigParams modelRig(const DaemonConfig& config) {
  sim::RigParams rig = config.modelRealistic ? sim::RigParams::realistic() : sim::RigParams::ideal();
  rig.framesPerSlice = config.modelPositions;
  rig.sweepSeconds = config.modelSweepSeconds;
  rig.seed = static_cast<std::uint64_t>(config.modelSeed);
  return rig;
}

// The camera the configuration asks for, and its name.
std::pair<CameraDescription, std::string> describeCamera(const DaemonConfig& config) {
  switch (config.camera) {
    case DaemonConfig::CameraKind::Libcamera:
      return {LiveCameraDescription{hal::DeviceBackend::Libcamera, config.cameraDevice},
              "libcamera " + (config.cameraDevice.empty() ? std::string("(the first camera)")
                                                          : config.cameraDevice)};
    case DaemonConfig::CameraKind::V4l2: {
      const std::string device = config.cameraDevice.empty() ? "/dev/video0" : config.cameraDevice;
      return {LiveCameraDescription{hal::DeviceBackend::V4l2, device}, "v4l2 " + device};
    }
    case DaemonConfig::CameraKind::Model:
      return {ModelCameraDescription{modelRig(config), config.modelMaterial, modelSensor(config)},
              "model camera"};
    case DaemonConfig::CameraKind::File:
      return {FileCameraDescription{config.recording, config.recordingSpeed}, "file camera " + config.recording.string()};
  }
  return {LiveCameraDescription{}, "camera"};
}

// The camera's settings that are values (the frame duration is parsed in describeDevices).
hal::CameraConfig cameraConfigOf(const DaemonConfig& config) {
  hal::CameraConfig camera;
  camera.widthPx = config.widthPx;
  camera.heightPx = config.heightPx;
  camera.exposureUs = config.exposureUs;
  camera.gain = config.gain;
  camera.raw = config.cameraRaw;
  camera.readoutUs = config.readoutUs;
  camera.mainsHz = config.mainsHz;
  return camera;
}

}  // namespace

LedDescription describeLed(const DaemonConfig& config) {
  LedDescription led;
  if (config.camera == DaemonConfig::CameraKind::File ||
      config.camera == DaemonConfig::CameraKind::Model) {
    led.log = config.ledLog.empty() ? config.storage / "led.log" : config.ledLog;
    led.seenByModel = config.camera == DaemonConfig::CameraKind::Model;
  }
  led.gpio = hal::GpioLineSpec{config.ledChip, config.ledLine, config.ledActiveLow};
  return led;
}

// The values copied first, then each name parsed and each file read, from the daemon's own
// vocabulary down to the files, one module at a time (daemon, sim, hal, io): the description is
// the one place that reads a device key. None of these steps depends on another's result but the
// model's room light, which needs its rig (copied first).
DeviceDescription describeDevices(const DaemonConfig& config) {
  DeviceDescription devices;
  devices.led = describeLed(config);
  std::tie(devices.camera, devices.cameraName) = describeCamera(config);
  devices.cameraConfig = cameraConfigOf(config);
  devices.decoding = daemon::decodingModeFromString(config.decoding);
  auto* model = std::get_if<ModelCameraDescription>(&devices.camera);
  // model_room_light: the room's irradiance against the LED's face-on at the rig's distance.
  if (model) model->rig.ambientIrradiance = sim::roomIrradianceFor(model->rig, config.modelRoomLight);
  devices.cameraConfig.frameDurationUs = hal::frameDurationUsForMains(config.mainsHz);
  if (model) {
    // model_raw: the model's sensor offers a RAW stream, taken as camera_raw says.
    if (!config.modelRaw.empty())
      model->sensor.rawFormat = hal::bayerFormatFromLibcameraName(config.modelRaw);
    model->sensor.pipeline = *hal::parseModelPipeline(config.modelPipeline);  // checked when read
  }
  devices.rig.target =
      config.target == "default" ? vision::defaultTarget() : io::readTargetJson(config.target);
  devices.rig.camera = config.calibration.empty()
                           ? vision::defaultSimulatedCamera()
                           : io::cameraFromJson(io::readJsonFile(config.calibration),
                                                config.calibration.string(), "");
  return devices;
}

}  // namespace slicecap::rig
