// slicecapd's configuration file (/etc/slicecap/slicecapd.conf): every field, its default, its
// check.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace slicecap::daemon {

/// \brief A configuration that cannot be used; what() is "FILE:LINE: key: what is wrong" (or
/// "FILE: ..." for file-level problems).
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief The daemon's settings. The file is `key = value` lines; `#` starts a comment; blank lines
/// are ignored; unknown keys and repeated keys are errors (a typo must not silently fall back to a
/// default).
struct DaemonConfig {
  enum class CameraKind { Libcamera, V4l2, File };

  // Camera.
  CameraKind camera = CameraKind::Libcamera;  ///< camera = libcamera | v4l2 | file
  std::string cameraDevice;  ///< camera_device: libcamera id or /dev/videoN; empty = first found
  std::filesystem::path
      recording;       ///< camera_recording: for camera = file, a recording or session folder
  int widthPx = 1280;  ///< resolution = WIDTHxHEIGHT
  int heightPx = 720;
  /// exposure_us: locked exposure; empty = metered at each sweep start, then locked
  /// (daemon::ExposureMeter)
  std::optional<double> exposureUs;
  /// gain: locked gain; empty = the camera's default while metered, else its auto gain runs
  std::optional<double> gain;
  std::filesystem::path
      calibration;  ///< calibration: camera intrinsics (slicecap calibrate output)

  // LED.
  std::string ledChip = "gpiochip0";  ///< led_chip: the GPIO chip (name or /dev path)
  std::string ledLine = "GPIO17";     ///< led_line: the line's name (e.g. GPIO17) or its offset
  bool ledActiveLow = false;          ///< led_active_low: the driver switches on at a low level
  bool ledAlternate = true;      ///< led_alternate: LED off every other frame for ambient removal
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
