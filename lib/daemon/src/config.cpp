// Parsing and checking slicecapd.conf.
#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/hdr_cycle.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/model_isp.hpp"

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
    throw ConfigError("'" + value + "' is not " + what);
  }
  return number;
}

int wholeNumber(const std::string& value, int lo, int hi, const std::string& what) {
  int number = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (ec != std::errc() || end != value.data() + value.size() || number < lo || number > hi)
    throw ConfigError("'" + value + "' is not a whole number in " + std::to_string(lo) +
                      ".." + std::to_string(hi) + " (" + what + ")");
  return number;
}

double numberIn(const std::string& value, double lo, double hi, const std::string& what) {
  double number = 0.0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (value.empty() || ec != std::errc() || end != value.data() + value.size() ||
      !(number >= lo && number <= hi))
    throw ConfigError("'" + value + "' is not " + what);
  return number;
}

bool boolean(const std::string& value) {
  if (value == "true" || value == "yes" || value == "1") return true;
  if (value == "false" || value == "no" || value == "0") return false;
  throw ConfigError("'" + value + "' is not true or false");
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
         throw ConfigError("'" + v + "' is not libcamera, v4l2, file or model");
     }},
    {"camera_device", [](DaemonConfig& c, const std::string& v) { c.cameraDevice = v; }},
    {"camera_recording", [](DaemonConfig& c, const std::string& v) { c.recording = v; }},
    {"camera_recording_speed",
     [](DaemonConfig& c, const std::string& v) {
       c.recordingSpeed = numberIn(v, 0.01, 1000.0, "a speed from 0.01 to 1000 (1: as recorded)");
     }},
    {"resolution",
     [](DaemonConfig& c, const std::string& v) {
       const auto x = v.find('x');
       if (x == std::string::npos) throw ConfigError("'" + v + "' is not WIDTHxHEIGHT");
       const double w = positiveNumber(v.substr(0, x), "a width"),
                    h = positiveNumber(v.substr(x + 1), "a height");
       if (w != std::floor(w) || h != std::floor(h) || w > 8192 || h > 8192 || w < 64 || h < 64) {
         throw ConfigError("'" + v + "' must be whole pixels between 64 and 8192");
       }
       c.widthPx = int(w);
       c.heightPx = int(h);
     }},
    {"exposure_us",
     [](DaemonConfig& c, const std::string& v) {
       c.exposureUs = v.empty() ? std::nullopt
                                : std::optional(positiveNumber(v, "a positive exposure in us"));
     }},
    {"hdr_levels",
     [](DaemonConfig& c, const std::string& v) {
       c.hdrLevels = wholeNumber(v, 1, kMaxHdrLevels, "exposures an HDR sweep alternates (1: no HDR)");
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
    {"room_light_unseen_mm",
     [](DaemonConfig& c, const std::string& v) {
       c.roomLightUnseenMm = numberIn(v, 0.0, 1000.0, "a distance in mm from 0 (off) to 1000");
     }},
    {"mains_hz",
     [](DaemonConfig& c, const std::string& v) {
       // Never a silent default: a frame duration pinned to the wrong flicker hides nothing.
       if (v == "50" || v == "60" || v == "0")
         c.mainsHz = std::stoi(v);
       else
         throw ConfigError("'" + v + "' is not 50, 60 or 0 (the mains frequency of the " +
                           "room's lights in Hz; 0: do not pin the frame duration)");
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
         throw ConfigError("'" + v + "' is not a read noise in 0..0.5 of full scale");
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
    {"refuse_broken_decoding",
     [](DaemonConfig& c, const std::string& v) { c.refuseBrokenDecoding = boolean(v); }},
    {"camera_raw",
     [](DaemonConfig& c, const std::string& v) {
       const std::optional<hal::RawCapture> raw = hal::parseRawCapture(v);
       if (!raw) throw ConfigError("'" + v + "' is not auto, on or off");
       c.cameraRaw = *raw;
     }},
    {"tuning_file",
     [](DaemonConfig& c, const std::string& v) {
       // A path is read and checked at start-up (slicecapd), where a bad file is refused.
       const std::optional<hal::TuningFileSetting> setting = hal::parseTuningFileSetting(v);
       if (!setting)
         throw ConfigError("'' is not auto, off or a tuning file's path");
       c.tuningFile = *setting;
     }},
  };
}

// With camera = model: the virtual rig and its camera.
std::vector<SetterEntry> modelCameraSetters() {
  return {
    {"model_raw",
     [](DaemonConfig& c, const std::string& v) {
       if (!v.empty() && !hal::bayerFormatFromLibcameraName(v))
         throw ConfigError("'" + v + "' is not a RAW format slicecap decodes (" +
                           "SRGGB10_CSI2P, SBGGR12, ...: S + the CFA order + 10, 12 " +
                           "or 16 bits, _CSI2P for 10 or 12 packed)");
       c.modelRaw = v;
     }},
    {"model_material", [](DaemonConfig& c, const std::string& v) { c.modelMaterial = v; }},
    {"model_rig",
     [](DaemonConfig& c, const std::string& v) {
       if (v != "realistic" && v != "ideal")
         throw ConfigError("'" + v + "' is not realistic or ideal");
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
         throw ConfigError("'" + v + "' is not imx708, srgb or linear");
       c.modelToneCurve = v;
     }},
    {"model_seed",
     [](DaemonConfig& c, const std::string& v) {
       c.modelSeed = wholeNumber(v, 0, 1'000'000'000, "a seed");
     }},
    {"model_room_light",
     [](DaemonConfig& c, const std::string& v) {
       c.modelRoomLight = numberIn(v, 0.0, 10.0, "a fraction of the LED's irradiance in 0..10");
     }},
    {"model_flicker_hz",
     [](DaemonConfig& c, const std::string& v) {
       const double hz = numberIn(v, 0.0, 1000.0, "a frequency in Hz, 0 or 1..1000");
       if (hz > 0.0 && hz < 1.0)
         throw ConfigError("'" + v + "' is not a frequency in Hz, 0 or 1..1000");
       c.modelFlickerHz = hz;
     }},
    {"model_flicker_depth",
     [](DaemonConfig& c, const std::string& v) {
       c.modelFlickerDepth = numberIn(v, 0.0, 1.0, "a flicker depth in 0..1");
     }},
    {"model_pipeline",
     [](DaemonConfig& c, const std::string& v) {
       if (!hal::parseModelPipeline(v)) throw ConfigError("'" + v + "' is not vc4 or pisp");
       c.modelPipeline = v;
     }},
    {"model_adaptive_contrast",
     [](DaemonConfig& c, const std::string& v) { c.modelAdaptiveContrast = boolean(v); }},
    {"model_colour_matrix",
     [](DaemonConfig& c, const std::string& v) {
       if (v != "imx708" && v != "identity")
         throw ConfigError("'" + v + "' is not imx708 or identity");
       c.modelColourMatrix = v;
     }},
    {"model_stream",
     [](DaemonConfig& c, const std::string& v) {
       if (v != "rgb" && v != "rec709" && v != "sycc")
         throw ConfigError("'" + v + "' is not rgb, rec709 or sycc");
       c.modelStream = v;
     }},
    {"model_temporal_denoise",
     [](DaemonConfig& c, const std::string& v) {
       c.modelTemporalDenoise = numberIn(v, 0.0, 0.95, "a weight of the previous frame in 0..0.95");
     }},
    {"model_timestamp_jitter_us",
     [](DaemonConfig& c, const std::string& v) {
       c.modelTimestampJitterUs = numberIn(v, 0.0, 1000.0, "microseconds in 0..1000");
     }},
    {"model_lock_counting",
     [](DaemonConfig& c, const std::string& v) {
       if (v != "request" && v != "truth")
         throw ConfigError("'" + v + "' is not request or truth");
       c.modelLocksCountedByRequest = v == "request";
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
         throw ConfigError("'" + v + "' is not a number of microseconds in 0..10000");
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
    } catch (const ConfigError& e) {
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
  // Each exposure level's room light comes from its own LED-off frames.
  if (config.hdrLevels > 1 && !config.ledAlternate)
    throw ConfigError(where + "hdr_levels = " + std::to_string(config.hdrLevels) +
                      " needs led_alternate = true (each exposure's room light is measured with "
                      "the LED off at that exposure)");
  return config;
}

DaemonConfig readDaemonConfig(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path.string() + ": cannot open the configuration file");
  return parseDaemonConfig(in, path.string());
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
  if (config.camera == DaemonConfig::CameraKind::V4l2 && config.hdrLevels > 1) {
    // libcamera reports each frame's own exposure; a V4L2 frame only the control's value, and a
    // sensor that takes a new exposure a frame or two after the driver would be read at the wrong
    // one (16 x off between HDR levels).
    warnings.push_back(
        "camera = v4l2 with hdr_levels = " + std::to_string(config.hdrLevels) +
        ": V4L2 frames do not report the exposure they were taken at, so a frame exposed just "
        "after a level change may be read at the other level's exposure; use camera = libcamera "
        "for HDR where the camera has a libcamera driver");
  }
  return warnings;
}

}  // namespace slicecap::daemon
