// The status's decoding check and tuning file as JSON.
#include "decoding_views.hpp"

#include "reply_fields.hpp"

namespace slicecap::control {

using nlohmann::json;
using reply_fields::field;
using reply_fields::optionalField;

json toJson(const DecodingCheckView& check) {
  json object = json::object();
  if (check.blackReading) object["black_reading"] = *check.blackReading;
  if (check.blackReadingStep) object["black_reading_step"] = *check.blackReadingStep;
  if (check.blackReadingStepSigmas)
    object["black_reading_step_sigmas"] = *check.blackReadingStepSigmas;
  if (check.windowAtBlackChannel) object["window_at_black_channel"] = *check.windowAtBlackChannel;
  if (check.windowAtBlack) object["window_at_black"] = *check.windowAtBlack;
  if (check.windowUnlitChannel) object["window_unlit_channel"] = *check.windowUnlitChannel;
  if (check.windowUnlit) object["window_unlit"] = *check.windowUnlit;
  if (check.windowUnlitAtZero) object["window_unlit_at_zero"] = *check.windowUnlitAtZero;
  if (check.windowUnlitSigmas) object["window_unlit_sigmas"] = *check.windowUnlitSigmas;
  if (check.windowUnlitMeanSigmas)
    object["window_unlit_mean_sigmas"] = *check.windowUnlitMeanSigmas;
  if (check.windowUnlitVerdict) object["window_unlit_verdict"] = *check.windowUnlitVerdict;
  if (check.windowStepChannel) object["window_step_channel"] = *check.windowStepChannel;
  if (check.windowStep) object["window_step"] = *check.windowStep;
  if (check.windowStepSigmas) object["window_step_sigmas"] = *check.windowStepSigmas;
  return object;
}

DecodingCheckView decodingCheckFromJson(const json& object) {
  return {optionalField<double>(object, "black_reading"),
          optionalField<double>(object, "black_reading_step"),
          optionalField<double>(object, "black_reading_step_sigmas"),
          optionalField<std::string>(object, "window_at_black_channel"),
          optionalField<double>(object, "window_at_black"),
          optionalField<std::string>(object, "window_unlit_channel"),
          optionalField<double>(object, "window_unlit"),
          optionalField<double>(object, "window_unlit_at_zero"),
          optionalField<double>(object, "window_unlit_sigmas"),
          optionalField<double>(object, "window_unlit_mean_sigmas"),
          optionalField<std::string>(object, "window_unlit_verdict"),
          optionalField<std::string>(object, "window_step_channel"),
          optionalField<double>(object, "window_step"),
          optionalField<double>(object, "window_step_sigmas")};
}

json toJson(const TuningFileView& tuning) {
  json object = {{"setting", tuning.setting}, {"reason", tuning.reason}};
  object["file"] = tuning.file ? json(*tuning.file) : json(nullptr);
  return object;
}

TuningFileView tuningFileFromJson(const json& object) {
  return {field<std::string>(object, "setting"), optionalField<std::string>(object, "file"),
          field<std::string>(object, "reason")};
}

}  // namespace slicecap::control
