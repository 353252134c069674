// A FramePipeline as the FrameProcessor the daemon and the offline commands call per frame; an
// HDR sweep's frames go to one pipeline per exposure level.
#include <map>
#include <memory>

#include "slicecap/capture/frame_pipeline.hpp"

namespace slicecap::capture {
namespace {

// The pipelines of one sweep, made as their first frame comes: one for frames without an
// exposure level (a sweep of one exposure), one per level of an HDR sweep. Per level, as
// processRecording does offline: an LED-on frame's room light is then read from an LED-off frame
// of its own exposure, and every sample carries its window cells for the per-bin merge
// (hdr_merge.hpp). With `--ambient previous` offline processing is the same, frame for frame.
class LevelPipelines {
 public:
  LevelPipelines(const vision::TargetGeometry& target, const vision::CameraModel& camera,
                 const PipelineSettings& settings)
      : target_(target), camera_(camera), settings_(settings) {
    // Made now, so that a bad target or camera throws here, not at the first frame.
    pipelines_.emplace(kNoLevel, FramePipeline(target_, camera_, settings_));
  }

  // The frame's pipeline; a shorter level's (level > 0) tracks from the longest level's latest
  // location when it is more recent than its own (FramePipeline::trackFrom), as
  // processRecording does offline.
  FramePipeline& forFrame(const hal::Frame& frame) {
    const int key = frame.metadata.exposureLevel.value_or(kNoLevel);
    auto found = pipelines_.find(key);
    if (found == pipelines_.end()) {
      PipelineSettings settings = settings_;
      if (key != kNoLevel) settings.hdr = true;
      found = pipelines_.emplace(key, FramePipeline(target_, camera_, settings)).first;
    }
    if (key > kLongestLevel)
      if (const auto longest = pipelines_.find(kLongestLevel); longest != pipelines_.end())
        if (const std::optional<TimedPose> location = longest->second.latestLocation())
          found->second.trackFrom(*location);
    return found->second;
  }

 private:
  static constexpr int kNoLevel = -1;
  static constexpr int kLongestLevel = 0;
  vision::TargetGeometry target_;
  vision::CameraModel camera_;
  PipelineSettings settings_;
  std::map<int, FramePipeline> pipelines_;
};

}  // namespace

FrameProcessor makeFramePipeline(const vision::TargetGeometry& target,
                                 const vision::CameraModel& camera,
                                 const PipelineSettings& settings, FrameObserver observer) {
  auto pipelines = std::make_shared<LevelPipelines>(target, camera, settings);
  return [pipelines, observer = std::move(observer)](const hal::Frame& frame, const SliceId& slice) {
    FramePipeline& pipeline = pipelines->forFrame(frame);
    FrameOutcome outcome = pipeline.process(frame, slice);
    if (outcome.sample && outcome.sample->hdr && frame.metadata.exposureLevel)
      outcome.sample->hdr->exposureLevel = *frame.metadata.exposureLevel;
    if (observer)
      observer(frame, outcome,
               frame.metadata.ledOn ? pipeline.ambientTermsFor(frame.metadata.timestampUs)
                                    : std::vector<AmbientTerm>{});
    return outcome;
  };
}

}  // namespace slicecap::capture
