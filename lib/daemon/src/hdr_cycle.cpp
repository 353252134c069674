// A live HDR sweep's exposure cycle: levels by LED-pair blocks, frames labelled by their exposure.
#include "slicecap/daemon/hdr_cycle.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "slicecap/daemon/slicecapd_error.hpp"

namespace slicecap::daemon {

std::optional<std::string> HdrCycle::refusal(const hal::ExposureSetting& longest,
                                             const HdrCycleParams& params) {
  if (params.levels < 2 || params.levels > kMaxHdrLevels)
    return "HDR: a cycle has 2 to " + std::to_string(kMaxHdrLevels) + " levels, not " +
           std::to_string(params.levels);
  if (!(params.stepRatio > 1.0) || params.pairsPerLevel < 1 || !(params.shortenOnClip > 1.0))
    return "HDR: the cycle needs a step ratio and shortening above 1 and a pair per level";
  if (!(longest.exposureUs > params.minExposureUs))
    return "HDR: the sweep's exposure (" + std::to_string(longest.exposureUs) +
           " us) leaves no room for a shorter level";
  return std::nullopt;
}

HdrCycle::HdrCycle(hal::ExposureSetting longest, HdrCycleParams params)
    : params_(params), gain_(longest.gain) {
  if (const std::optional<std::string> why = refusal(longest, params_)) throw SlicecapdError(*why);
  double exposureUs = longest.exposureUs;
  for (int k = 0; k < params_.levels; ++k) {
    levelsUs_.push_back(exposureUs);
    heldUs_.push_back({exposureUs});
    exposureUs = std::max(params_.minExposureUs, exposureUs / params_.stepRatio);
  }
}

hal::ExposureSetting HdrCycle::settingOf(int level) const {
  return {levelsUs_[static_cast<std::size_t>(level)], gain_};
}

std::optional<hal::ExposureSetting> HdrCycle::pairStarted() {
  if (++pairsAtLevel_ <= params_.pairsPerLevel) return std::nullopt;
  pairsAtLevel_ = 1;
  level_ = (level_ + 1) % params_.levels;
  return settingOf(level_);
}

void HdrCycle::accepted(int level, const hal::ExposureSetting& setting) {
  // The camera's own value (clamped, quantised to its line time) is what its frames report.
  levelsUs_.at(static_cast<std::size_t>(level)) = setting.exposureUs;
  std::vector<double>& held = heldUs_[static_cast<std::size_t>(level)];
  if (held.back() != setting.exposureUs) held.push_back(setting.exposureUs);  // one per change
}

int HdrCycle::levelOf(const hal::FrameMetadata& metadata) const {
  if (!(metadata.exposureUs > 0.0)) return level_;
  int nearest = 0;
  double best = INFINITY;
  for (std::size_t k = 0; k < heldUs_.size(); ++k)
    for (const double heldUs : heldUs_[k]) {
      const double distance = std::abs(std::log(metadata.exposureUs / heldUs));
      if (distance < best) best = distance, nearest = static_cast<int>(k);
    }
  return nearest;
}

bool HdrCycle::shortestClipped(const hal::FrameMetadata& metadata) {
  double& shortest = levelsUs_.back();
  // Below shortenOnClip x the present value: not a frame of the exposure this level had before.
  if (metadata.exposureUs > 0.0 && metadata.exposureUs > shortest * std::sqrt(params_.shortenOnClip))
    return false;
  const double shortened = std::max(params_.minExposureUs, shortest / params_.shortenOnClip);
  if (!(shortened < shortest)) return false;
  shortest = shortened;
  heldUs_.back().push_back(shortened);
  ++shortenings_;
  return true;
}

std::string HdrCycle::summary() const {
  std::string line = "HDR, " + std::to_string(levelsUs_.size()) + " exposures by LED pairs (";
  for (std::size_t k = 0; k < levelsUs_.size(); ++k) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%s%.0f us", k ? ", " : "", levelsUs_[k]);
    line += buffer;
  }
  line += ")";
  if (shortenings_ > 0)
    line += "; the shortest shortened " + std::to_string(shortenings_) +
            " time(s) where the window clipped";
  return line;
}

}  // namespace slicecap::daemon
