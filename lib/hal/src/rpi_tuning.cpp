// Which Raspberry Pi tuning file the processed path runs with, and the start-up check of it.
#include "slicecap/hal/rpi_tuning.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slicecap/hal/camera_error.hpp"

namespace slicecap::hal {

std::optional<TuningFileSetting> parseTuningFileSetting(std::string_view text) {
  if (text.empty()) return std::nullopt;
  if (text == "auto") return TuningFileSetting{TuningFileSetting::Kind::Auto, {}};
  if (text == "off") return TuningFileSetting{TuningFileSetting::Kind::Off, {}};
  return TuningFileSetting{TuningFileSetting::Kind::Path, std::filesystem::path(text)};
}

std::string_view tuningTarget(PiIsp isp) { return isp == PiIsp::Pisp ? "pisp" : "bcm2835"; }

std::optional<PiIsp> piIspOfCompatible(std::string_view compatible) {
  // The strings are NUL-separated; a board lists its model first, then its SoC.
  std::size_t start = 0;
  std::optional<PiIsp> isp;
  while (start < compatible.size()) {
    std::size_t end = compatible.find('\0', start);
    if (end == std::string_view::npos) end = compatible.size();
    const std::string_view entry = compatible.substr(start, end - start);
    if (entry == "brcm,bcm2712") return PiIsp::Pisp;
    if (entry == "brcm,bcm2711" || entry == "brcm,bcm2837" || entry == "brcm,bcm2836" ||
        entry == "brcm,bcm2835")
      isp = PiIsp::Vc4;
    start = end + 1;
  }
  return isp;
}

bool processedPathRuns(const TuningInputs& inputs) {
  if (inputs.raw == RawCapture::Off) return true;
  if (inputs.raw == RawCapture::On) return false;
  return inputs.rawGranted.has_value() && !*inputs.rawGranted;
}

TuningChoice chooseTuningFile(const TuningFileSetting& setting, const TuningInputs& inputs) {
  using Kind = TuningFileSetting::Kind;
  if (setting.kind == Kind::Off) return {std::nullopt, "tuning_file = off: the camera's own tuning file"};
  if (!processedPathRuns(inputs))
    return {std::nullopt,
            std::string("no tuning file set: the camera runs RAW (") +
                (inputs.raw == RawCapture::On ? "camera_raw = on"
                 : inputs.rawGranted          ? "granted"
                                              : "camera_raw = auto, expected") +
                "), which bypasses the ISP a tuning file tunes"};
  if (setting.kind == Kind::Path)
    return {setting.path, "tuning_file = " + setting.path.string() + " for the processed path"};
  if (!inputs.isp)
    return {std::nullopt, "tuning_file = auto: not a Raspberry Pi, the camera's own tuning"};
  if (inputs.sensorModel.empty())
    return {std::nullopt, "tuning_file = auto: the sensor is unknown, the camera's own tuning"};
  const std::filesystem::path file =
      inputs.tuningDir / ("slicecap-" + inputs.sensorModel + "-" +
                          (*inputs.isp == PiIsp::Pisp ? "pisp" : "vc4") + ".json");
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error))
    return {std::nullopt, "tuning_file = auto: slicecap has no tuning file for the " +
                              inputs.sensorModel + " (no " + file.string() +
                              "): the camera's own tuning, adaptive contrast included; the "
                              "response curve's residual gate refuses a curve that does not fit"};
  return {file, "tuning_file = auto: " + file.string() + " for the processed path"};
}

void validateTuningFile(const std::filesystem::path& file, std::optional<PiIsp> isp) {
  const auto refuse = [&file](const std::string& why) {
    throw CameraError("tuning_file " + file.string() + ": " + why);
  };
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) refuse("is a directory, not a tuning file");
  std::ifstream in(file, std::ios::binary);
  if (!in) refuse("cannot be read (" + std::string(std::strerror(errno)) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& parseError) {
    refuse(std::string("is not valid JSON: ") + parseError.what());
  }
  if (!root.is_object()) refuse("is not a JSON object");
  const auto version = root.find("version");
  if (version == root.end() || !version->is_number() || version->get<double>() < 2.0 ||
      version->get<double>() >= 3.0)
    refuse("has no \"version\" 2.x (the Raspberry Pi IPA's tuning format, controller.cpp)");
  const auto algorithms = root.find("algorithms");
  if (algorithms == root.end() || !algorithms->is_array() || algorithms->empty())
    refuse("has no \"algorithms\" list");
  const auto target = root.find("target");
  const std::string targetText =
      target != root.end() && target->is_string() ? target->get<std::string>() : "";
  if (targetText != "bcm2835" && targetText != "pisp")
    refuse("has no \"target\" of \"bcm2835\" or \"pisp\"");
  if (isp && targetText != tuningTarget(*isp))
    refuse("is for \"" + targetText + "\", but this Raspberry Pi's ISP is \"" +
           std::string(tuningTarget(*isp)) + "\" (its IPA would refuse the file)");
}

std::filesystem::path slicecapTuningDir() {
  const std::filesystem::path installed(SLICECAP_TUNING_INSTALL_DIR);
  std::error_code error;
  if (std::filesystem::is_directory(installed, error)) return installed;
  return SLICECAP_TUNING_SOURCE_DIR;
}

}  // namespace slicecap::hal
