// The session journal's records as JSON.
#include "journal_records.hpp"

namespace slicecap::capture::journal_records {

nlohmann::json sliceJson(const SliceId& s) {
  return {{"kind", toString(s.kind)},
          {"theta_i", s.elevations.thetaIDeg},
          {"theta_v", s.elevations.thetaVDeg}};
}

SliceId sliceFrom(const nlohmann::json& j) {
  const auto kind = parseSliceKind(j.at("kind").get<std::string>());
  if (!kind) throw std::invalid_argument("unknown slice kind");
  return {*kind, {wholeNumber(j, "theta_i", 0, 89), wholeNumber(j, "theta_v", 0, 89)}};
}

}  // namespace slicecap::capture::journal_records
