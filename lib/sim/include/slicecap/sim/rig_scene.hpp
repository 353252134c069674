// The virtual rig as the scene in front of the model camera: the hand-held camera goes once
// round a slice, and the renderer gives the LED's and the room's light at each moment.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "slicecap/core/slice.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"

namespace slicecap::sim {

/// \brief One sweep of the virtual rig as a hal::SceneSource. The camera and the light move
/// through rig.framesPerSlice planned positions (planSweep, with the rig's imperfections) in
/// rig.sweepSeconds, resting sweepSeconds / framesPerSlice at each, after holding still at the
/// first for `holdSeconds` (a person keeps the rig still while the daemon meters the exposure);
/// the scene ends after the last.
/// Light is rendered noise-free (the model camera adds the sensor's noise) and cached per
/// position.
class RigScene final : public hal::SceneSource {
 public:
  /// \brief Throws SimError for invalid rig parameters.
  RigScene(std::shared_ptr<const FrameRenderer> renderer, const SliceId& slice,
           const RigParams& rig, double holdSeconds = 0.0);
  std::string id() const override;
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t sinceStartUs) override;
  /// \brief The planned positions (tests compare the capture's poses with them).
  const std::vector<FramePlan>& plans() const { return plans_; }
  /// \brief Time spent at each position, microseconds.
  double dwellUs() const { return dwellUs_; }

 private:
  std::shared_ptr<const FrameRenderer> renderer_;
  SliceId slice_;
  std::vector<FramePlan> plans_;
  double dwellUs_;
  double holdUs_;
  std::mutex mutex_;
  std::size_t cachedIndex_ = SIZE_MAX;
  std::shared_ptr<const hal::SceneLight> cached_;
};

}  // namespace slicecap::sim
