// slicecapd's configuration file (/etc/slicecap/slicecapd.conf): every field, its default, its
// check.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/core/error.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/rpi_tuning.hpp"

namespace slicecap::daemon {

/// \brief A configuration that cannot be used; what() is "FILE:LINE: key: what is wrong" (or
/// "FILE: ..." for file-level problems).
class ConfigError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief The daemon's settings. The file is `key = value` lines; `#` starts a comment; blank lines
/// are ignored; unknown keys and repeated keys are errors (a typo must not silently fall back to a
/// default).
struct DaemonConfig {
  enum class CameraKind { Libcamera, V4l2, File, Model };

  // Camera.
  CameraKind camera = CameraKind::Libcamera;  ///< camera = libcamera | v4l2 | file | model
  std::string cameraDevice;  ///< camera_device: libcamera id or /dev/videoN; empty = first found
  std::filesystem::path
      recording;       ///< camera_recording: for camera = file, a recording or session folder
  double recordingSpeed = 1.0;  ///< camera_recording_speed: the recording played this x faster
  int widthPx = 1280;  ///< resolution = WIDTHxHEIGHT
  int heightPx = 720;
  /// exposure_us: locked exposure; empty = metered at each sweep start, then locked
  /// (daemon::ExposureMeter)
  std::optional<double> exposureUs;
  /// gain: locked gain; empty = the camera's default while metered, else its auto gain runs
  std::optional<double> gain;
  int hdrLevels = 1;  ///< hdr_levels: exposures an HDR sweep alternates by LED-pair blocks
  std::filesystem::path
      calibration;  ///< calibration: camera intrinsics (slicecap calibrate output)
  /// readout_us: the sensor's top-to-bottom readout time (slicecapd --check-hardware measures
  /// it); empty: the camera's line time where it says it, else a whole frame period.
  std::optional<double> readoutUs;
  /// mains_hz = 50 | 60 | 0: the room lights' mains frequency; 50 or 60 pins every frame to a
  /// whole number of their flicker periods (hal::frameDurationUsForMains), 0 leaves the camera's
  /// own frame duration.
  int mainsHz = 0;
  /// room_light_unseen_mm: capture::PipelineSettings::maxRoomLightDistanceMm (0: off).
  double roomLightUnseenMm = 0.0;
  /// sensor_read_noise, sensor_full_well_electrons: the frames' noise as the white-reference
  /// test expects it (capture::SensorNoise; slicecapd --check-hardware measures both).
  double sensorReadNoise = 0.002;
  double sensorFullWellElectrons = 8000.0;
  /// decoding = auto | measured-curve | srgb: how 8-bit live frames become linear light
  /// (daemon::DecodingMode; docs/linear-light.md "In the daemon").
  std::string decoding = "auto";
  /// refuse_broken_decoding: a sweep run whose 8-bit decoding is shown broken (a window channel
  /// the LED does not light, DecodingWatch::refusal) has its slice's samples set aside as it
  /// ends; false: only warned about (docs/real-sensors.md, "Refused sweeps").
  bool refuseBrokenDecoding = true;
  /// camera_raw = auto | on | off: the RAW (Bayer) stream, decoded to linear light, where the
  /// camera offers a format slicecap decodes (hal::RawCapture).
  hal::RawCapture cameraRaw = hal::RawCapture::Auto;
  /// tuning_file = auto | off | PATH: the Raspberry Pi tuning file the processed path runs with
  /// (hal::chooseTuningFile; set as LIBCAMERA_RPI_TUNING_FILE before libcamera starts).
  hal::TuningFileSetting tuningFile{};

  // camera = model: the virtual rig in front of a camera model that behaves like a Pi camera
  // (hal::ModelCamera): a material, the rig's imperfections, the sweep's pace, the ISP's curve.
  std::string modelMaterial = "satin-blue-45";  ///< model_material: a `slicecap simulate` material
  bool modelRealistic = true;       ///< model_rig = realistic | ideal
  double modelSweepSeconds = 8.0;   ///< model_sweep_seconds: one sweep's time round the slice
  int modelPositions = 32;          ///< model_positions: where the hand rests on the way round
  std::string modelToneCurve = "imx708";  ///< model_tone_curve = imx708 | srgb | linear
  int modelSeed = 7;                      ///< model_seed: the rig's and the sensor's randomness
  /// model_raw: the RAW format the model's sensor offers (a libcamera name slicecap decodes, e.g.
  /// SRGGB10_CSI2P, a Pi 4's IMX708); empty = none, the model offers processed frames only.
  std::string modelRaw;
  /// model_room_light: the room light's irradiance on the target as a fraction of the LED's,
  /// face-on at the rig's light distance (the virtual rig's ambient irradiance follows from it).
  double modelRoomLight = 0.10;
  /// model_flicker_hz, model_flicker_depth: the room light's flicker (hal::SensorModel).
  double modelFlickerHz = 100.0;
  double modelFlickerDepth = 0.10;
  /// model_pipeline = vc4 | pisp: the Pi whose validation the RAW request meets (hal::ModelPipeline).
  std::string modelPipeline = "pisp";
  /// The ISP of the processed stream and the frames' metadata (hal::ModelIsp), as a Pi's:
  /// model_adaptive_contrast (rpi.contrast ce_enable), model_colour_matrix = imx708 | identity
  /// (rpi.ccm), model_stream = rgb | rec709 | sycc (the stream's YCbCr coding), model_temporal_denoise
  /// (the previous output's weight on a Pi 5; 0 off), model_timestamp_jitter_us, model_lock_counting
  /// = request | truth.
  bool modelAdaptiveContrast = true;
  std::string modelColourMatrix = "identity";
  std::string modelStream = "rgb";
  double modelTemporalDenoise = 0.5;
  double modelTimestampJitterUs = 20.0;
  bool modelLocksCountedByRequest = true;

  // LED.
  std::string ledChip = "gpiochip0";  ///< led_chip: the GPIO chip (name or /dev path)
  std::string ledLine = "GPIO17";     ///< led_line: the line's name (e.g. GPIO17) or its offset
  bool ledActiveLow = false;          ///< led_active_low: the driver switches on at a low level
  bool ledAlternate = true;      ///< led_alternate: LED off in blocks of frames for ambient removal
  int ledFramesPerState = 2;     ///< led_frames_per_state: frames on, then as many off
  double ledGuardUs = 200.0;     ///< led_guard_us: a switch's uncertainty either side
  std::filesystem::path ledLog;  ///< led_log: with camera = file, where the file LED logs changes

  // Target and storage.
  std::string target = "default";  ///< target: "default" (built in) or a target JSON path
  std::filesystem::path storage = "/var/lib/slicecap";  ///< storage: where sessions live
  bool recordFrames = false;  ///< record_frames: also keep raw frames as recordings
  int textureResolution = 0;    ///< texture_resolution: texels across the window; 0 = no texture
  int textureFramesPerBin = 5;  ///< texture_frames_per_bin: frames a texture bin keeps

  // Control socket.
  std::filesystem::path socket =
      "/run/slicecap/slicecapd.sock";    ///< socket (when not socket-activated)
  std::string socketGroup = "slicecap";  ///< socket_group: who may talk to the daemon; empty = keep
  /// client_idle_timeout_s: a client that sends nothing for this long is closed; 0 = never
  int clientIdleTimeoutS = 300;

  /// \brief The file's text with the defaults, every key documented: what `slicecapd
  /// --print-config` writes and the package installs.
  static std::string documentedDefaults();
};

/// \brief Parses configuration text; `sourceName` names it in errors. Throws ConfigError.
DaemonConfig parseDaemonConfig(std::istream& in, const std::string& sourceName);

/// \brief What a valid configuration still does wrong for a real capture, one sentence each
/// (empty when nothing): slicecapd logs them at start and `--check-config` prints them.
std::vector<std::string> configWarnings(const DaemonConfig& config);

/// \brief Reads and parses a configuration file; ConfigError naming the file if it cannot be read.
DaemonConfig readDaemonConfig(const std::filesystem::path& path);

}  // namespace slicecap::daemon
