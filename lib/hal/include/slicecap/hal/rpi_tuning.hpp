// slicecap's Raspberry Pi tuning file for the processed path (data/tuning/, installed under
// /usr/share/slicecap/tuning/): which file a libcamera camera runs with, and the check that it
// can be read, before libcamera's one CameraManager starts.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slicecap/hal/camera.hpp"

namespace slicecap::hal {

/// \brief slicecapd.conf's tuning_file: `auto` (slicecap's file where the processed path runs
/// on a sensor it has one for), `off` (the camera's own tuning file), or a file's path.
struct TuningFileSetting {
  enum class Kind { Auto, Off, Path };
  Kind kind = Kind::Auto;
  std::filesystem::path path;  ///< Kind::Path only
};

/// \brief "auto", "off", or any other non-empty text as a path; nullopt for empty text.
std::optional<TuningFileSetting> parseTuningFileSetting(std::string_view text);

/// \brief The Raspberry Pi ISP a board has, which a tuning file's "target" must name: "bcm2835"
/// (VideoCore 4: Pi 4 and earlier) or "pisp" (Pi 5). The Pi's IPA refuses a file for the
/// other one (src/ipa/rpi/vc4/vc4.cpp and pisp/pisp.cpp platformInit).
enum class PiIsp { Vc4, Pisp };

/// \brief The tuning file's "target" for `isp`: "bcm2835" or "pisp".
std::string_view tuningTarget(PiIsp isp);

/// \brief The ISP of the board whose device tree root lists `compatible` (the NUL-separated
/// strings of /proc/device-tree/compatible): "brcm,bcm2712" is a Pi 5 (PiSP); bcm2711, bcm2837,
/// bcm2836 and bcm2835 are VideoCore 4; nullopt for anything else (not a Raspberry Pi).
std::optional<PiIsp> piIspOfCompatible(std::string_view compatible);

/// \brief What the camera is, as far as slicecapd can tell before it opens it.
struct TuningInputs {
  RawCapture raw = RawCapture::Auto;
  /// Whether the camera's validation grants a RAW stream slicecap decodes (the probe's
  /// CameraModes::validatedRaw); nullopt when not probed.
  std::optional<bool> rawGranted;
  std::string sensorModel;      ///< libcamera's properties::Model, e.g. "imx708"; empty: unknown
  std::optional<PiIsp> isp;     ///< nullopt: not a Raspberry Pi
  std::filesystem::path tuningDir;  ///< where slicecap's tuning files are
};

/// \brief The file LIBCAMERA_RPI_TUNING_FILE is set to (nullopt: left unset, the camera's own
/// tuning), and why, for the log.
struct TuningChoice {
  std::optional<std::filesystem::path> file;
  std::string reason;
};

/// \brief Whether the processed path runs: camera_raw off, or auto with no RAW granted.
bool processedPathRuns(const TuningInputs& inputs);

/// \brief The file for `setting`: off never; a path, or auto's slicecap-<sensor>-<isp>.json in
/// `tuningDir` when it exists, only where the processed path runs (RAW bypasses the ISP the file
/// tunes, and keeps the camera's own black level and focus); auto also needs a Raspberry Pi ISP
/// and a sensor slicecap has a file for.
TuningChoice chooseTuningFile(const TuningFileSetting& setting, const TuningInputs& inputs);

/// \brief Checks that `file` is a Raspberry Pi tuning file the IPA will read: readable, JSON,
/// version 2.x with an "algorithms" list, and a "target" of "bcm2835" or "pisp" (the one of
/// `isp` when known). Throws CameraError naming the file and the reason: the IPA would otherwise
/// fail the camera with a message in libcamera's log only, or a file silently replaced would run
/// an ISP the measurement does not expect.
void validateTuningFile(const std::filesystem::path& file, std::optional<PiIsp> isp);

/// \brief Where slicecap's own tuning files are: the installed /usr/share/slicecap/tuning when it
/// exists, else the source tree's data/tuning (a build that is not installed).
std::filesystem::path slicecapTuningDir();

}  // namespace slicecap::hal
