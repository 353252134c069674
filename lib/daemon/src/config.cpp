// Parsing and checking slicecapd.conf.
#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"

#include "slicecap/hal/bayer_frame.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

namespace slicecap::daemon {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

double positiveNumber(const std::string& value, const std::string& what) {
  double number = 0.0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(number) ||
      number <= 0.0) {
    throw std::invalid_argument("'" + value + "' is not " + what);
  }
  return number;
}

int wholeNumber(const std::string& value, int lo, int hi, const std::string& what) {
  int number = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (ec != std::errc() || end != value.data() + value.size() || number < lo || number > hi)
    throw std::invalid_argument("'" + value + "' is not a whole number in " + std::to_string(lo) +
                                ".." + std::to_string(hi) + " (" + what + ")");
  return number;
}

bool boolean(const std::string& value) {
  if (value == "true" || value == "yes" || value == "1") return true;
  if (value == "false" || value == "no" || value == "0") return false;
  throw std::invalid_argument("'" + value + "' is not true or false");
}

using Setter = std::function<void(DaemonConfig&, const std::string&)>;

using SetterEntry = std::pair<const char*, Setter>;

// The camera and its frames.
std::vector<SetterEntry> cameraSetters() {
  return {
    {"camera",
     [](DaemonConfig& c, const std::string& v) {
       if (v == "libcamera")
         c.camera = DaemonConfig::CameraKind::Libcamera;
       else if (v == "v4l2")
         c.camera = DaemonConfig::CameraKind::V4l2;
       else if (v == "file")
         c.camera = DaemonConfig::CameraKind::File;
       else if (v == "model")
         c.camera = DaemonConfig::CameraKind::Model;
       else
         throw std::invalid_argument("'" + v + "' is not libcamera, v4l2, file or model");
     }},
    {"camera_device", [](DaemonConfig& c, const std::string& v) { c.cameraDevice = v; }},
    {"camera_recording", [](DaemonConfig& c, const std::string& v) { c.recording = v; }},
    {"resolution",
     [](DaemonConfig& c, const std::string& v) {
       const auto x = v.find('x');
       if (x == std::string::npos) throw std::invalid_argument("'" + v + "' is not WIDTHxHEIGHT");
       const double w = positiveNumber(v.substr(0, x), "a width"),
                    h = positiveNumber(v.substr(x + 1), "a height");
       if (w != std::floor(w) || h != std::floor(h) || w > 8192 || h > 8192 || w < 64 || h < 64) {
         throw std::invalid_argument("'" + v + "' must be whole pixels between 64 and 8192");
       }
       c.widthPx = int(w);
       c.heightPx = int(h);
     }},
    {"exposure_us",
     [](DaemonConfig& c, const std::string& v) {
       c.exposureUs = v.empty() ? std::nullopt
                                : std::optional(positiveNumber(v, "a positive exposure in us"));
     }},
    {"gain",
     [](DaemonConfig& c, const std::string& v) {
       c.gain = v.empty() ? std::nullopt : std::optional(positiveNumber(v, "a positive gain"));
     }},
    {"calibration", [](DaemonConfig& c, const std::string& v) { c.calibration = v; }},
    {"readout_us",
     [](DaemonConfig& c, const std::string& v) {
       c.readoutUs = v.empty() ? std::nullopt
                               : std::optional(positiveNumber(v, "a positive readout time in us"));
     }},
  };
}

// The sensor's noise and how its frames become linear light.
std::vector<SetterEntry> sensorSetters() {
  return {
    {"sensor_read_noise",
     [](DaemonConfig& c, const std::string& v) {
       char* end = nullptr;
       const double noise = std::strtod(v.c_str(), &end);
       if (v.empty() || *end != '\0' || !(noise >= 0 && noise < 0.5))
         throw std::invalid_argument("'" + v + "' is not a read noise in 0..0.5 of full scale");
       c.sensorReadNoise = noise;
     }},
    {"sensor_full_well_electrons",
     [](DaemonConfig& c, const std::string& v) {
       c.sensorFullWellElectrons = positiveNumber(v, "a positive number of electrons");
     }},
    {"decoding",
     [](DaemonConfig& c, const std::string& v) {
       decodingModeFromString(v);  // throws naming the value
       c.decoding = v;
     }},
    {"camera_raw",
     [](DaemonConfig& c, const std::string& v) {
       const std::optional<hal::RawCapture> raw = hal::parseRawCapture(v);
       if (!raw) throw std::invalid_argument("'" + v + "' is not auto, on or off");
       c.cameraRaw = *raw;
     }},
  };
}

// With camera = model: the virtual rig and its camera.
std::vector<SetterEntry> modelCameraSetters() {
  return {
    {"model_raw",
     [](DaemonConfig& c, const std::string& v) {
       if (!v.empty() && !hal::bayerFormatFromLibcameraName(v))
         throw std::invalid_argument("'" + v + "' is not a RAW format slicecap decodes (" +
                                     "SRGGB10_CSI2P, SBGGR12, ...: S + the CFA order + 10, 12 " +
                                     "or 16 bits, _CSI2P for 10 or 12 packed)");
       c.modelRaw = v;
     }},
    {"model_material", [](DaemonConfig& c, const std::string& v) { c.modelMaterial = v; }},
    {"model_rig",
     [](DaemonConfig& c, const std::string& v) {
       if (v != "realistic" && v != "ideal")
         throw std::invalid_argument("'" + v + "' is not realistic or ideal");
       c.modelRealistic = v == "realistic";
     }},
    {"model_sweep_seconds",
     [](DaemonConfig& c, const std::string& v) {
       c.modelSweepSeconds = positiveNumber(v, "a positive number of seconds");
     }},
    {"model_positions",
     [](DaemonConfig& c, const std::string& v) {
       c.modelPositions = wholeNumber(v, 8, 1000, "positions round a sweep");
     }},
    {"model_tone_curve",
     [](DaemonConfig& c, const std::string& v) {
       if (v != "imx708" && v != "srgb" && v != "linear")
         throw std::invalid_argument("'" + v + "' is not imx708, srgb or linear");
       c.modelToneCurve = v;
     }},
    {"model_seed",
     [](DaemonConfig& c, const std::string& v) {
       c.modelSeed = wholeNumber(v, 0, 1'000'000'000, "a seed");
     }},
  };
}

// The LED: its GPIO line and how it is switched.
std::vector<SetterEntry> ledSetters() {
  return {
    {"led_chip", [](DaemonConfig& c, const std::string& v) { c.ledChip = v; }},
    {"led_line", [](DaemonConfig& c, const std::string& v) { c.ledLine = v; }},
    {"led_active_low",
     [](DaemonConfig& c, const std::string& v) { c.ledActiveLow = boolean(v); }},
    {"led_alternate", [](DaemonConfig& c, const std::string& v) { c.ledAlternate = boolean(v); }},
    {"led_frames_per_state",
     [](DaemonConfig& c, const std::string& v) {
       c.ledFramesPerState = wholeNumber(v, 1, 30, "frames the LED holds each state");
     }},
    {"led_guard_us",
     [](DaemonConfig& c, const std::string& v) {
       char* end = nullptr;
       const double guard = std::strtod(v.c_str(), &end);
       if (v.empty() || *end != '\0' || !(guard >= 0 && guard <= 10000))
         throw std::invalid_argument("'" + v + "' is not a number of microseconds in 0..10000");
       c.ledGuardUs = guard;
     }},
    {"led_log", [](DaemonConfig& c, const std::string& v) { c.ledLog = v; }},
  };
}

// The target, where sessions, recordings and textures are kept, and the control socket.
std::vector<SetterEntry> storageSetters() {
  return {
    {"target", [](DaemonConfig& c, const std::string& v) { c.target = v; }},
    {"storage", [](DaemonConfig& c, const std::string& v) { c.storage = v; }},
    {"record_frames", [](DaemonConfig& c, const std::string& v) { c.recordFrames = boolean(v); }},
    {"texture_resolution",
     [](DaemonConfig& c, const std::string& v) {
       c.textureResolution = wholeNumber(v, 0, 512, "texels across the window (0: off)");
     }},
    {"texture_frames_per_bin",
     [](DaemonConfig& c, const std::string& v) {
       c.textureFramesPerBin = wholeNumber(v, 1, 64, "frames a bin keeps");
     }},
    {"socket", [](DaemonConfig& c, const std::string& v) { c.socket = v; }},
    {"socket_group", [](DaemonConfig& c, const std::string& v) { c.socketGroup = v; }},
    {"client_idle_timeout_s",
     [](DaemonConfig& c, const std::string& v) {
       c.clientIdleTimeoutS = wholeNumber(v, 0, 86400, "seconds; 0: never");
     }},
  };
}

// Every key's setter, the sections' tables in one map.
const std::map<std::string, Setter>& setters() {
  static const std::map<std::string, Setter> table = [] {
    std::map<std::string, Setter> all;
    for (const auto& section : {cameraSetters(), sensorSetters(), modelCameraSetters(),
                                ledSetters(), storageSetters()})
      all.insert(section.begin(), section.end());
    return all;
  }();
  return table;
}

}  // namespace

DaemonConfig parseDaemonConfig(std::istream& in, const std::string& sourceName) {
  DaemonConfig config;
  std::set<std::string> seen;
  std::string line;
  for (int lineNumber = 1; std::getline(in, line); ++lineNumber) {
    const std::string text = trim(line.substr(0, line.find('#')));
    if (text.empty()) continue;
    const std::string where = sourceName + ":" + std::to_string(lineNumber) + ": ";
    const auto equals = text.find('=');
    if (equals == std::string::npos)
      throw ConfigError(where + "expected 'key = value', got '" + text + "'");
    const std::string key = trim(text.substr(0, equals));
    const std::string value = trim(text.substr(equals + 1));
    const auto setter = setters().find(key);
    if (setter == setters().end()) throw ConfigError(where + "unknown key '" + key + "'");
    if (!seen.insert(key).second) throw ConfigError(where + key + ": set twice");
    try {
      setter->second(config, value);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(where + key + ": " + e.what());
    }
  }
  // Whole-file rules: a setting that makes sense only with another.
  const std::string where = sourceName + ": ";
  if (config.camera == DaemonConfig::CameraKind::File && config.recording.empty()) {
    throw ConfigError(
        where + "camera = file needs camera_recording (a recording or simulated session folder)");
  }
  if (config.storage.is_relative()) throw ConfigError(where + "storage must be an absolute path");
  if (config.socket.is_relative()) throw ConfigError(where + "socket must be an absolute path");
  if (config.ledLine.empty()) throw ConfigError(where + "led_line must name the LED's GPIO line");
  return config;
}

DaemonConfig readDaemonConfig(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path.string() + ": cannot open the configuration file");
  return parseDaemonConfig(in, path.string());
}

namespace {

// slicecapd --print-config, one constant per group of keys; documentedDefaults() joins them with
// a blank line between groups.

// What the file is.
constexpr const char* kHeaderDefaults = R"(# slicecapd configuration. `key = value`; `#` starts a comment. Unknown keys are errors.
# The daemon checks every field when it starts and names the line of any mistake.
)";
// The camera, its frames and how they become linear light.
constexpr const char* kCameraDefaults = R"(# Camera: libcamera (Raspberry Pi camera modules), v4l2 (USB cameras), file (plays a recording
# or a simulated session) or model (the virtual rig in front of a model of a Pi camera: queued
# buffers, rolling shutter, late controls, the ISP's curve; for tests and demonstrations).
camera = libcamera
# libcamera camera id or /dev/videoN; empty takes the first camera found.
camera_device =
# With camera = file: the recording or simulated session folder to play.
camera_recording =
# Frame size in pixels.
resolution = 1280x720
# Locked exposure (microseconds) and gain (the camera's own units: V4L2's gain control, libcamera's
# analogue gain). Empty exposure_us: each sweep start meters it with the LED on (the brightest
# 0.5 % of the image brought to 0.35 of full scale, about a second, at most 33.3 ms: a darker
# scene needs more gain) and locks it, with gain at its value here or the camera's default, for
# the sweep; `slicecap status` shows what was locked.
# Set exposure_us when a glossy material's highlight clips (frames rejected as window_clipped).
exposure_us =
gain =
# Camera intrinsics and distortion (from `slicecap calibrate`); empty uses the sensor's nominal model.
calibration =
# The sensor's readout time, top row to bottom row, in microseconds (`slicecapd --check-hardware`
# measures it). Empty: the camera's line time where it reports one, else a whole frame period
# (safe, but it rejects more frames as led_transition).
readout_us =
# The frames' noise, which the white-reference test allows for (an 8-bit frame's references near
# black disagree by noise alone): read noise as a fraction of full scale, and shot noise as the
# electrons a full-scale value stands for at gain 1. `slicecapd --check-hardware` measures both;
# the defaults are a small 8-bit camera module's.
sensor_read_noise = 0.002
sensor_full_well_electrons = 8000
# How 8-bit frames become linear light. auto: at each sweep start, right after the metering and
# with the LED on, a bracket of 8 exposures (x1/32 .. x4, about a second) of the target's white and
# black references measures the camera's response curve, and every frame of the sweep is decoded
# through it; a camera delivering linear 16-bit frames needs none. Hold the target still and in
# view meanwhile. A bracket that cannot be fitted (target not in view, clipping, a camera that
# cannot lock or report its exposure) falls back to sRGB, with a warning in `slicecap status`
# naming the camera. measured-curve: the same. srgb: no bracket; frames decoded as sRGB (only for
# a camera known to encode sRGB).
decoding = auto
)";
// The sensor's RAW stream.
constexpr const char* kCameraRawDefaults = R"(# The sensor's RAW (Bayer) stream, black level off and 2 x 2 binned into linear light (half the
# sensor mode's size: a camera module 3 asked for 1280x720 delivers 1152x648; calibrate at that
# size): auto takes it where the camera offers a format slicecap decodes (10/12-bit, packed or
# not; a Pi 5's compressed RAW is not, and the processed stream is used), on requires it, off
# never takes it (docs/real-sensors.md).
camera_raw = auto
)";
// With camera = model: the virtual rig.
constexpr const char* kModelCameraDefaults = R"(# With camera = model: the material (any `slicecap simulate --material`), the rig (realistic:
# hand-held jitter, blur, occlusion, room light; ideal: none), seconds per sweep, the positions the
# hand rests at on the way round, the ISP's tone curve (imx708: the Pi camera module 3's tuning),
# the seed of the rig's and the sensor's randomness, and the RAW format its sensor offers (empty:
# none; SRGGB10_CSI2P: a Pi 4's camera module 3; taken as camera_raw says).
model_material = satin-blue-45
model_rig = realistic
model_sweep_seconds = 8
model_positions = 32
model_tone_curve = imx708
model_seed = 7
model_raw =
)";
// The LED.
constexpr const char* kLedDefaults = R"(# LED: the GPIO chip and line that drive the LED driver (never an LED straight on a pin; see
# firmware/README.md). The line by name (as `gpioinfo` lists it) or by offset.
led_chip = gpiochip0
led_line = GPIO17
led_active_low = false
# Switch the LED off in blocks of frames, so ambient light can be measured and removed. false: the
# LED stays on and no room light is removed (only for a dark room).
led_alternate = true
# Frames the LED holds each state (on, then off). Each switch is timed from the camera's
# timestamps to fall where no row of the window or the white references is being exposed; a frame
# it falls in anyway is rejected as led_transition. A camera that cannot say when it exposed
# needs 4 or more.
led_frames_per_state = 2
# How long either side of a switch a row's exposure is not trusted (GPIO call, driver, LED rise).
led_guard_us = 200
# With camera = file: the file the LED's changes are written to (empty: <storage>/led.log).
led_log =
)";
// The target and where sessions and recordings are kept.
constexpr const char* kStorageDefaults = R"(# The printed target: "default" (slicecap target's built-in one) or a target JSON file.
target = default
# Where sessions are kept (one folder each; samples are on disk before they are acknowledged).
storage = /var/lib/slicecap
# Also keep every raw frame of a sweep (LED on and off) as a recording in the session's folder,
# <storage>/<session>/recordings/<kind>-<theta_i>-<theta_v>, to re-process the session on a desktop
# (`slicecap capture-offline <session>/recordings`). A writer thread saves the PNGs; frames that
# arrive while 4 wait are left out of the recording (counted in `slicecap status`), never out of
# the sweep; a full disk stops the recording, not the sweep. About 1-3 MB a 720p frame.
record_frames = false
)";
// Texture (BTF) capture.
constexpr const char* kTextureDefaults = R"(# Texture (BTF) capture: with N > 0 every accepted frame's window is also rectified to N x N texels
# (64, 128 or 256 are typical; 0 switches it off) and kept per azimuth bin, at most
# texture_frames_per_bin frames a bin (those nearest its centre), in <storage>/<session>/texture.
# Disk: 8 slices x 24 bins x that many frames x N^2 x 6 bytes at most (N = 128, 5 frames: 94 MB);
# memory only the index. `slicecap export` copies it; `slicecap btf EXPORT/<id>-texture -o DIR`
# reconstructs the BTF (on the box or a desktop). A session keeps the resolution it started with.
texture_resolution = 0
texture_frames_per_bin = 5
)";
// The control socket.
constexpr const char* kSocketDefaults = R"(# The control socket, when systemd does not pass one (slicecapd.socket), and the group allowed to use it.
socket = /run/slicecap/slicecapd.sock
socket_group = slicecap
# A client that sends no request for this many seconds is closed (0: never), so connections left
# open cannot hold all 128 client slots. `slicecap status --watch` asks every --interval seconds.
client_idle_timeout_s = 300
)";

}  // namespace

std::string DaemonConfig::documentedDefaults() {
  std::string text;
  for (const char* group :
       {kHeaderDefaults, kCameraDefaults, kCameraRawDefaults, kModelCameraDefaults, kLedDefaults,
        kStorageDefaults, kTextureDefaults, kSocketDefaults})
    text += (text.empty() ? "" : "\n") + std::string(group);
  return text;
}

std::vector<std::string> configWarnings(const DaemonConfig& config) {
  std::vector<std::string> warnings;
  if (config.camera == DaemonConfig::CameraKind::V4l2 && config.exposureUs && !config.gain) {
    // An empty exposure_us is metered and locked, gain with it, at each sweep start; a set
    // exposure is taken as it is, so an empty gain leaves the camera's auto gain running, and a
    // V4L2 frame does not say its gain: LED-on and LED-off frames may differ in it.
    warnings.push_back(
        "camera = v4l2 with exposure_us set and gain empty: the camera's auto gain runs and its "
        "frames do not say their gain, so room light is subtracted at a gain that may not be the "
        "LED-on frame's; set gain too, or leave both empty to have them metered at sweep start");
  }
  return warnings;
}

}  // namespace slicecap::daemon
