// The virtual rig's sweep as the model camera's scene: a position per dwell, two renders each.
#include "slicecap/sim/rig_scene.hpp"

#include <algorithm>
#include <stdexcept>

#include "slicecap/sim/sim_error.hpp"

namespace slicecap::sim {

RigScene::RigScene(std::shared_ptr<const FrameRenderer> renderer, const SliceId& slice,
                   const RigParams& rig, double holdSeconds)
    : renderer_(std::move(renderer)), slice_(slice), holdUs_(std::max(0.0, holdSeconds) * 1e6) {
  std::string why;
  if (!renderer_) throw SimError("rig scene: no renderer");
  if (!rig.isValid(&why)) throw SimError("rig scene: " + why);
  plans_ = planSweep(slice, kAxialOffsetDeg, rig, renderer_->camera(), renderer_->target());
  dwellUs_ = rig.sweepSeconds * 1e6 / double(plans_.size());
}

std::string RigScene::id() const {
  return "virtual rig, " + toString(slice_);
}

std::shared_ptr<const hal::SceneLight> RigScene::lightAt(std::int64_t sinceStartUs) {
  const double movingUs = double(sinceStartUs) - holdUs_;
  const std::size_t index = movingUs < 0 ? 0 : static_cast<std::size_t>(movingUs / dwellUs_);
  if (index >= plans_.size()) return nullptr;
  std::lock_guard lock(mutex_);
  if (index == cachedIndex_) return cached_;
  const FramePlan& plan = plans_[index];
  // Per second of exposure at unit gain: the model camera scales by its own exposure and gain.
  FrameScene scene{plan.exposurePoses, plan.lightMm, true, 1e6, 1.0, plan.occluder, 0};
  const std::vector<float> lit = renderer_->renderLinear(scene);
  scene.ledOn = false;
  auto light = std::make_shared<hal::SceneLight>();
  light->widthPx = renderer_->camera().intrinsics.widthPx;
  light->heightPx = renderer_->camera().intrinsics.heightPx;
  light->ambientRate = renderer_->renderLinear(scene);
  light->ledRate.resize(lit.size());
  for (std::size_t i = 0; i < lit.size(); ++i)
    light->ledRate[i] = std::max(0.0f, lit[i] - light->ambientRate[i]);
  cachedIndex_ = index;
  cached_ = std::move(light);
  return cached_;
}

}  // namespace slicecap::sim
