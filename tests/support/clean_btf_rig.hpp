// The ideal virtual rig the BTF tests render on, its LED-on frames and a sweep's plans with the
// exposure a person would set.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "slicecap/hal/frame.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::test {

// An ideal rig on 16-bit linear frames with no room light and the LED always on: what is left to
// get wrong is the geometry and radiometry of the texture itself.
inline sim::RigParams cleanRig(int frames) {
  sim::RigParams rig = sim::RigParams::ideal();
  rig.encoding = PixelEncoding::Linear16;
  rig.ambientIrradiance = 0.0;
  rig.alternateLed = false;
  rig.framesPerSlice = frames;
  return rig;
}

// The LED-on frame of a plan, rendered.
inline hal::Frame renderedFrame(const sim::FrameRenderer& renderer, const sim::FramePlan& plan) {
  sim::FrameScene scene;
  scene.exposurePoses = plan.exposurePoses;
  scene.lightMm = plan.lightMm;
  scene.exposureUs = plan.exposureUs;
  scene.gain = plan.gain;
  Image image = renderer.render(scene);
  hal::Frame frame{std::move(image), PixelEncoding::Linear16, {}};
  frame.metadata = {std::uint64_t(plan.index), plan.timestampUs, plan.exposureUs, plan.gain, true};
  return frame;
}

// The plans of a sweep with the exposure a person would set.
inline std::vector<sim::FramePlan> plannedSweep(const SliceId& slice, const sim::RigParams& rig,
                                                const sim::FrameRenderer& renderer) {
  std::vector<sim::FramePlan> plans =
      sim::planSweep(slice, kAxialOffsetDeg, rig, renderer.camera(), renderer.target());
  const double exposureUs = sim::chooseExposureUs(renderer, rig, plans);
  for (sim::FramePlan& plan : plans)
    plan.exposureUs = std::round(exposureUs * plan.exposureScale);
  return plans;
}

}  // namespace slicecap::test
