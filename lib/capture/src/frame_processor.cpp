// A FramePipeline as the FrameProcessor the daemon and the offline commands call per frame.
#include <memory>

#include "slicecap/capture/frame_pipeline.hpp"

namespace slicecap::capture {

FrameProcessor makeFramePipeline(const vision::TargetGeometry& target,
                                 const vision::CameraModel& camera,
                                 const PipelineSettings& settings, FrameObserver observer) {
  auto pipeline = std::make_shared<FramePipeline>(target, camera, settings);
  return [pipeline, observer = std::move(observer)](const hal::Frame& frame, const SliceId& slice) {
    FrameOutcome outcome = pipeline->process(frame, slice);
    if (observer)
      observer(frame, outcome,
               frame.metadata.ledOn ? pipeline->ambientTermsFor(frame.metadata.timestampUs)
                                    : std::vector<AmbientTerm>{});
    return outcome;
  };
}

}  // namespace slicecap::capture
