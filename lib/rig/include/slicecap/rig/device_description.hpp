// slicecapd.conf's devices as typed values, read from the configuration once: what the daemon
// and `--check-hardware` open (configured_devices.hpp), so neither reads a key again.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <variant>

#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/device_backends.hpp"
#include "slicecap/hal/gpiod_led.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::rig {

/// \brief The target and camera model of a slice's sweep.
struct Rig {
  vision::TargetGeometry target;
  vision::CameraModel camera;
};

/// \brief camera = libcamera or v4l2: the backend and its device (libcamera's camera id, empty
/// for the first camera; a V4L2 device node).
struct LiveCameraDescription {
  hal::DeviceBackend backend = hal::DeviceBackend::Libcamera;
  std::string device;
};

/// \brief camera = model: the virtual rig in front of it, its material's specification (read when
/// the camera opens) and its sensor as the sweep runs it (the check holds the scene still and
/// runs it on a simulated clock).
struct ModelCameraDescription {
  sim::RigParams rig;
  std::string materialSpec;
  hal::SensorModel sensor;
};

/// \brief camera = file: the recording, or a session folder of them (read when the camera opens).
struct FileCameraDescription {
  std::filesystem::path recording;
  double speed = 1.0;  ///< the recording's time against the clock's (camera_recording_speed)
};

using CameraDescription =
    std::variant<LiveCameraDescription, ModelCameraDescription, FileCameraDescription>;

/// \brief The LED: a file LED's log (camera = file or model; camera = model also sees its light),
/// or the GPIO line.
struct LedDescription {
  std::optional<std::filesystem::path> log;
  bool seenByModel = false;
  hal::GpioLineSpec gpio;
};

/// \brief Every device setting of slicecapd.conf, its names and values parsed.
struct DeviceDescription {
  CameraDescription camera;
  /// \brief The camera as the configuration names it ("libcamera (the first camera)", "v4l2
  /// /dev/video0", "model camera", "file camera PATH"): the check's report when it cannot open.
  std::string cameraName;
  /// \brief What the daemon and the check ask of the camera: size, exposure and gain when set,
  /// RAW, readout time, the frame duration the mains frequency asks for.
  hal::CameraConfig cameraConfig;
  /// \brief How its 8-bit frames are read (`decoding`).
  daemon::DecodingMode decoding = daemon::DecodingMode::Auto;
  LedDescription led;
  /// \brief The configured target (`target`: default or a target JSON) and camera model
  /// (`calibration`, else the default camera module 3 at 1280 x 720).
  Rig rig;
};

/// \brief The devices of `config`, parsed once. Reads the target and calibration files (throws
/// io::IoError naming the one that cannot be read); opens no device and reads no recording or
/// material (the camera factory does, where its failure is the camera's).
DeviceDescription describeDevices(const daemon::DaemonConfig& config);

/// \brief The LED of `config` alone (`--led-off`: reads no file).
LedDescription describeLed(const daemon::DaemonConfig& config);

}  // namespace slicecap::rig
