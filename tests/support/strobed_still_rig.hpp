// The decoding checks' figures (scripts/decoding-check-figures): the rig held still over
// satin-blue-45, read by the model camera with its fixed ISP (adaptive contrast on or off), the LED
// switched every 3 frame periods.
#pragma once

#include <cstdint>
#include <memory>

#include "bracket_rig.hpp"
#include "slicecap/capture/area_reading.hpp"
#include "slicecap/hal/model_isp_stage.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::test {

/// \brief An area of a frame of the still rig (stillPose, the default camera), per unit exposure:
/// the area's mean as the pipeline reads it, without a clip limit or a noise model.
inline Rgb stillAreaMean(const hal::Frame& frame, const vision::RectMm& rect,
                         const capture::CodeTable& codes) {
  return capture::readArea(frame, stillPose(), vision::defaultSimulatedCamera(), {rect, 0.0, 2.0},
                           {}, codes)
      .mean;
}

/// \brief The still rig over satin-blue-45, and the areas the figures read on its target.
struct StillSatinRig {
  std::shared_ptr<StillScene> scene;
  vision::RectMm black;  ///< the black patch
  vision::RectMm white;  ///< a 6 x 16 mm strip of the white-left reference
  vision::TargetGeometry target;

  StillSatinRig() {
    const auto renderer = std::make_shared<sim::FrameRenderer>(
        vision::defaultSimulatedCamera(), vision::defaultTarget(),
        sim::loadMaterial("satin-blue-45"), sim::RigParams::ideal());
    scene = std::make_shared<StillScene>(renderer, stillPose(), stillLightMm());
    target = renderer->target();
    for (const vision::Patch& p : target.patches)
      if (p.kind == vision::PatchKind::Black) black = p.rect;
    const vision::PointMm w = target.patches.front().rect.centre();  // white-left
    white = {w.xMm - 3, w.yMm - 8, w.xMm + 3, w.yMm + 8};
  }
};

/// \brief The model camera over `scene` at its metered exposure, the LED switched on and off
/// every 3 frame periods at `phase` of a period after a frame's start, `switches` times.
struct StrobedStillCamera {
  hal::SensorModel model;
  double exposureUs = 0.0;
  hal::FakeClock clock{1'000'000};
  std::shared_ptr<hal::LedTimeline> led = std::make_shared<hal::LedTimeline>(true);
  std::unique_ptr<hal::ModelCamera> camera;
  bool locked = false;  ///< whether the exposure locked

  StrobedStillCamera(const std::shared_ptr<StillScene>& scene, bool adaptiveContrast, double phase,
                     int switches) {
    model.isp = hal::fixedModelIsp();
    model.isp.adaptiveContrast = adaptiveContrast;
    exposureUs = BracketRig(scene, model).meteredExposureUs();
    model.realTime = false;
    for (int k = 3; k < 3 * switches; k += 3)
      led->record(1'000'000 + std::int64_t((k + phase) * model.framePeriodUs), (k / 3) % 2 == 0);
    camera = std::make_unique<hal::ModelCamera>(scene, led, clock, model);
    hal::CameraConfig config;
    camera->configure(config);
    camera->start();
    locked = camera->lockExposure({exposureUs, 1.0}).locked.has_value();
  }
};

}  // namespace slicecap::test
