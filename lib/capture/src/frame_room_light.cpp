// The frame pipeline's room light: LED-off frames located at their own poses, the terms an LED-on
// frame's room light is read from, and that light over a target area (FramePipeline::State).
#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "frame_pipeline_state.hpp"

namespace slicecap::capture {

FramePipeline::State::Ambient FramePipeline::State::makeAmbient(const hal::Frame& frame,
                                                                bool inTurn) {
  Ambient a{frame, std::nullopt};
  const bool acquiring = inTurn && !search.tracking();
  if (!settings.poseAmbientFrames && !acquiring) return a;
  std::vector<PlaneCorrespondence> corners;
  for (const auto& marker : search.search(frame, false).markers)
    if (const vision::Marker* geometry = target.findMarker(marker.id))
      for (int c = 0; c < 4; ++c)
        corners.push_back(
            {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
  if (static_cast<int>(corners.size()) < 4 * settings.minMarkers) return a;
  const auto estimate = estimatePlanarPose(corners, camera);
  if (!estimate || estimate->residualRmsPx > settings.maxPoseResidualPx) return a;
  if (acquiring) locatedAt(estimate->pose, frame.metadata.timestampUs);
  if (settings.poseAmbientFrames) a.pose = estimate->pose;
  return a;
}

std::optional<RowSpan> FramePipeline::State::litOwnRows(const Ambient& a) const {
  if (!a.pose) return std::nullopt;
  const RowSpan rows =
      rowsOfInterest(target, camera, *a.pose, a.frame.image.height, kBlurRowMarginPx);
  if (ledStateOver(a.frame, rows) == hal::LedExposure::State::Off) return std::nullopt;
  return rows;
}

std::optional<double> FramePipeline::State::roomChangeBetween(const Ambient& a,
                                                              const Ambient& b) const {
  if (!a.pose || !b.pose) return std::nullopt;
  double apart = 0.0, level = 0.0;
  for (const auto& reference : references) {
    AreaSpec area = reference.area;
    area.clipFraction = 2.0;
    const AreaReading ra = readArea(a.frame, *a.pose, camera, area, settings.noise, *codes);
    const AreaReading rb = readArea(b.frame, *b.pose, camera, area, settings.noise, *codes);
    if (!ra.inside || !rb.inside) continue;
    for (int c = 0; c < 3; ++c) {
      apart += std::abs(ra.mean[c] - rb.mean[c]);
      level += 0.5 * (ra.mean[c] + rb.mean[c]);
    }
  }
  if (!(level > 0.0)) return std::nullopt;
  return apart / level;
}

std::vector<AmbientTerm> FramePipeline::State::ambientTerms(
    std::int64_t timeUs, const std::optional<vision::Pose>& pose) const {
  std::vector<AmbientTerm> own = bracketingTerms(
      ambient ? &*ambient : nullptr, nextAmbient ? &*nextAmbient : nullptr, timeUs, pose);
  const bool ownLocated = !own.empty() && std::all_of(own.begin(), own.end(),
                                                      [](const AmbientTerm& t) { return t.pose; });
  if (ownLocated || standIns.empty()) return own;
  const auto after = std::find_if(standIns.begin(), standIns.end(), [&](const Ambient& a) {
    return a.frame.metadata.timestampUs > timeUs;
  });
  return bracketingTerms(after == standIns.begin() ? nullptr : &*std::prev(after),
                         after == standIns.end() ? nullptr : &*after, timeUs, pose);
}

std::vector<AmbientTerm> FramePipeline::State::bracketingTerms(
    const Ambient* before, const Ambient* after, std::int64_t timeUs,
    const std::optional<vision::Pose>& pose) {
  const auto term = [](const Ambient& a, double weight) {
    return AmbientTerm{&a.frame, a.pose, weight};
  };
  if (!before && !after) return {};
  if (!before) return {term(*after, 1.0)};
  if (!after || after->frame.metadata.timestampUs <= timeUs) return {term(*before, 1.0)};
  const double w =
      roomLightWeight({before->frame.metadata.timestampUs, before->pose},
                      {after->frame.metadata.timestampUs, after->pose}, {timeUs, pose});
  return {term(*before, 1.0 - w), term(*after, w)};
}

AreaReading FramePipeline::State::ambientAt(const std::vector<AmbientTerm>& terms, AreaSpec area,
                                            const vision::Pose& pose) const {
  area.clipFraction = 2.0;
  AreaReading sum;
  for (const AmbientTerm& term : terms) {
    AreaReading value;
    if (term.pose) value = readArea(*term.frame, *term.pose, camera, area, settings.noise, *codes);
    if (!value.inside) value = readArea(*term.frame, pose, camera, area, settings.noise, *codes);
    sum.mean += term.weight * value.mean;
    sum.variance += term.weight * term.weight * value.variance;
  }
  return sum;
}

}  // namespace slicecap::capture
