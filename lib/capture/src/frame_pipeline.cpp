// The per-frame pipeline: detect, pose, gate, measure the window against the white references.
#include "slicecap/capture/frame_pipeline.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "frame_checks.hpp"
#include "frame_pipeline_state.hpp"
#include "slicecap/capture/capture_error.hpp"

namespace slicecap::capture {

using namespace frame_checks;

FramePipeline::FramePipeline(vision::TargetGeometry target, vision::CameraModel camera,
                             PipelineSettings settings)
    : state_(std::make_unique<State>(std::move(target), std::move(camera), settings)) {
  std::string error;
  if (!state_->camera.isValid(&error))
    throw CaptureError("capture pipeline: camera: " + error);
  if (const auto problem = vision::findTargetProblem(state_->target))
    throw CaptureError("capture pipeline: target: " + *problem);
  if (!settings.noise.isValid(&error)) throw CaptureError("capture pipeline: " + error);
  const vision::RectMm& w = state_->target.window;
  const double half = settings.windowSampleFraction * std::min(w.widthMm(), w.heightMm()) / 2.0;
  const vision::PointMm c = w.centre();
  state_->windowArea.rectMm = {c.xMm - half, c.yMm - half, c.xMm + half, c.yMm + half};
  // Each white patch gives up to 4 observations (its quarters); the pixels near a quarter's
  // outline are left out (referenceInsetPx) so blur or a slightly wrong pose does not mix in the
  // window or a marker.
  for (const auto& patch : state_->target.patches) {
    if (patch.kind == vision::PatchKind::Black && !state_->black)
      state_->black = State::Reference{AreaSpec{patch.rect, settings.referenceInsetPx},
                                       {patch.rect.centre().xMm, patch.rect.centre().yMm},
                                       patch.albedo};
    if (patch.kind != vision::PatchKind::White) continue;
    const vision::RectMm& r = patch.rect;
    const int nx = r.widthMm() > 2 * r.heightMm() ? 4 : (r.widthMm() * 2 < r.heightMm() ? 1 : 2);
    const int ny = r.heightMm() > 2 * r.widthMm() ? 4 : (r.heightMm() * 2 < r.widthMm() ? 1 : 2);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x0 = r.xMinMm + i * r.widthMm() / nx, x1 = x0 + r.widthMm() / nx;
        const double y0 = r.yMinMm + j * r.heightMm() / ny, y1 = y0 + r.heightMm() / ny;
        const vision::RectMm part{x0, y0, x1, y1};
        state_->references.push_back({AreaSpec{part, settings.referenceInsetPx},
                                      {part.centre().xMm, part.centre().yMm},
                                      patch.albedo});
      }
  }
  if (state_->references.size() < 5)
    throw CaptureError("capture pipeline: target: fewer than 5 white reference areas");
}

FramePipeline::~FramePipeline() = default;
FramePipeline::FramePipeline(FramePipeline&&) noexcept = default;
FramePipeline& FramePipeline::operator=(FramePipeline&&) noexcept = default;

// A frame process() rejects as "bad_frame" is not read as room light either: its pixels are not
// where the LED-on frame's are, or not in its encoding.
void FramePipeline::setAmbientFrame(const hal::Frame& frame) {
  if (badFrameDetail(frame, state_->camera.intrinsics) || !offOverSampleRows(frame)) return;
  State::Ambient ambient = state_->makeAmbient(frame, false);
  if (!state_->litOwnRows(ambient)) state_->ambient = std::move(ambient);
}

void FramePipeline::setFollowingAmbientFrame(const hal::Frame& frame) {
  State& s = *state_;
  if (badFrameDetail(frame, s.camera.intrinsics) || !offOverSampleRows(frame)) return;
  if (s.nextAmbient && s.nextAmbient->frame.metadata.timestampUs == frame.metadata.timestampUs)
    return;
  State::Ambient ambient = s.makeAmbient(frame, false);
  if (!s.litOwnRows(ambient)) s.nextAmbient = std::move(ambient);
}

// An LED-off frame offered as room light (offline) is one only if the LED was off over the rows
// a sample reads, as process() judges it.
bool FramePipeline::offOverSampleRows(const hal::Frame& frame) const {
  const int height = frame.image.height;
  const RowSpan rows = state_->predictedRowsOfInterest(height).value_or(RowSpan{0, height - 1});
  return ledStateOver(frame, rows) == hal::LedExposure::State::Off;
}

void FramePipeline::setStandInAmbientFrames(std::vector<LocatedAmbientFrame> frames) {
  std::vector<State::Ambient>& standIns = state_->standIns;
  standIns.clear();
  for (LocatedAmbientFrame& f : frames)
    if (!badFrameDetail(f.frame, state_->camera.intrinsics))
      standIns.push_back({std::move(f.frame), f.pose});
}

std::optional<TimedPose> FramePipeline::latestLocation() const {
  const std::optional<vision::Pose>& pose = state_->search.lastPose();
  if (!pose) return std::nullopt;
  return TimedPose{*pose, *state_->lastLocatedUs};  // set wherever the search is given a pose
}

// Only a location newer than this pipeline's latest, tracked or given up: a pose its search
// dropped after missing with it is not taken back.
void FramePipeline::trackFrom(const TimedPose& location) {
  State& s = *state_;
  if (s.lastLocatedUs && *s.lastLocatedUs >= location.timestampUs) return;
  s.search.trackFrom(location.pose);
  s.lastLocatedUs = location.timestampUs;
}

std::vector<AmbientTerm> FramePipeline::ambientTermsFor(
    std::int64_t timeUs, const std::optional<vision::Pose>& pose) const {
  return state_->ambientTerms(timeUs, pose);
}

FrameOutcome FramePipeline::process(const hal::Frame& frame, const SliceId& slice) {
  State& s = *state_;
  const std::uint64_t index = s.frameIndex++;
  if (std::optional<FrameOutcome> done = s.screen(frame)) return std::move(*done);
  FrameOutcome outcome;
  Located located;
  if (auto rejection = s.locate(frame, outcome, located)) return std::move(*rejection);
  if (auto rejection = s.checkView(frame, slice, outcome, located)) return std::move(*rejection);
  FrameSample sample;
  sample.frameIndex = index;
  if (auto rejection = s.measure(frame, outcome, located, sample)) return std::move(*rejection);
  outcome.kind = FrameOutcome::Kind::Sample;
  outcome.sample = std::move(sample);
  outcome.detail = located.markerText;
  return outcome;
}

}  // namespace slicecap::capture
