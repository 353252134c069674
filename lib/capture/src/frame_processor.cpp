// A FramePipeline as the FrameProcessor the daemon and the offline commands call per frame; an
// HDR sweep's frames go to one pipeline per exposure level.
#include <algorithm>
#include <deque>
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

namespace {

// One frame through its level's pipeline, with what makeFramePipeline adds around it.
FrameOutcome processed(LevelPipelines& pipelines, const FrameObserver& observer,
                       const hal::Frame& frame, const SliceId& slice,
                       const hal::Frame* following = nullptr) {
  FramePipeline& pipeline = pipelines.forFrame(frame);
  if (following) pipeline.setFollowingAmbientFrame(*following);
  FrameOutcome outcome = pipeline.process(frame, slice);
  if (outcome.sample && outcome.sample->hdr && frame.metadata.exposureLevel)
    outcome.sample->hdr->exposureLevel = *frame.metadata.exposureLevel;
  if (observer)
    observer(frame, outcome,
             frame.metadata.ledOn
                 ? pipeline.ambientTermsFor(frame.metadata.timestampUs, outcome.measurement.pose)
                 : std::vector<AmbientTerm>{});
  return outcome;
}

// The LED-on frames waiting for the LED-off frame after them, per exposure level (an HDR
// sweep's LED-on frame takes the LED-off frames of its own level), in arrival order.
class HeldFrames {
 public:
  HeldFrames(const vision::TargetGeometry& target, const vision::CameraModel& camera,
             const PipelineSettings& settings, FrameObserver observer)
      : pipelines_(target, camera, settings),
        observer_(std::move(observer)),
        twoSided_(settings.requireAmbient) {}

  std::vector<SettledFrame> take(const hal::Frame* frame, const SliceId& slice) {
    std::vector<SettledFrame> settled;
    if (!frame) {
      // The stream ended: what is held settles one-sided, in capture order across levels.
      std::vector<hal::Frame> rest;
      for (auto& [level, frames] : held_)
        for (hal::Frame& f : frames) rest.push_back(std::move(f));
      held_.clear();
      std::stable_sort(rest.begin(), rest.end(), [](const hal::Frame& a, const hal::Frame& b) {
        return a.metadata.timestampUs < b.metadata.timestampUs;
      });
      for (const hal::Frame& f : rest) settle(f, slice, nullptr, settled);
      return settled;
    }
    if (!twoSided_) {
      settle(*frame, slice, nullptr, settled);
      return settled;
    }
    std::deque<hal::Frame>& level = held_[frame->metadata.exposureLevel.value_or(-1)];
    if (frame->metadata.ledOn) {
      level.push_back(*frame);
      return settled;
    }
    // The LED-off frame after the held ones: each takes it as its following room light.
    while (!level.empty()) {
      settle(level.front(), slice, frame, settled);
      level.pop_front();
    }
    settle(*frame, slice, nullptr, settled);
    return settled;
  }

 private:
  void settle(const hal::Frame& frame, const SliceId& slice, const hal::Frame* following,
              std::vector<SettledFrame>& settled) {
    settled.push_back({frame.metadata, processed(pipelines_, observer_, frame, slice, following)});
  }

  LevelPipelines pipelines_;
  FrameObserver observer_;
  bool twoSided_;
  std::map<int, std::deque<hal::Frame>> held_;
};

}  // namespace

LiveFrameProcessor makeLiveFramePipeline(const vision::TargetGeometry& target,
                                         const vision::CameraModel& camera,
                                         const PipelineSettings& settings, FrameObserver observer) {
  auto held = std::make_shared<HeldFrames>(target, camera, settings, std::move(observer));
  return [held](const hal::Frame* frame, const SliceId& slice) { return held->take(frame, slice); };
}

FrameProcessor makeFramePipeline(const vision::TargetGeometry& target,
                                 const vision::CameraModel& camera,
                                 const PipelineSettings& settings, FrameObserver observer) {
  auto pipelines = std::make_shared<LevelPipelines>(target, camera, settings);
  return [pipelines, observer = std::move(observer)](const hal::Frame& frame, const SliceId& slice) {
    return processed(*pipelines, observer, frame, slice);
  };
}

}  // namespace slicecap::capture
