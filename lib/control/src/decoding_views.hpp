// The JSON of the status's decoding check and tuning file (reply_views.cpp writes and reads the
// status with them).
#pragma once

#include <nlohmann/json.hpp>

#include "slicecap/control/reply_views.hpp"

namespace slicecap::control {

/// \brief Each figure known, none for an empty check.
nlohmann::json toJson(const DecodingCheckView& check);
/// \brief Throws as the status reader does for a key of the wrong type.
DecodingCheckView decodingCheckFromJson(const nlohmann::json& object);
nlohmann::json toJson(const TuningFileView& tuning);
TuningFileView tuningFileFromJson(const nlohmann::json& object);

}  // namespace slicecap::control
