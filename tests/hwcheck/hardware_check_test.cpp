// runHardwareCheck on the camera model, where every answer is known: the configured readout,
// LED delay, delivery latency, control delay and tone curve must come back (issue 27's goal:
// within 10 %); and on cameras that cannot answer (no target, no timestamps).
#include "slicecap/hwcheck/hardware_check.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "../support/bracket_rig.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/hwcheck/response_check.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"

namespace slicecap::hwcheck {
namespace {

class PlainLed final : public hal::Led {
 public:
  std::string id() const override { return "plain"; }
  void set(bool on) override { on_ = on; }
  bool isOn() const override { return on_; }

 private:
  bool on_ = false;
};

std::shared_ptr<test::StillScene> stillScene() {
  static const auto scene = [] {
    auto renderer = std::make_shared<sim::FrameRenderer>(
        vision::defaultSimulatedCamera(), vision::defaultTarget(),
        sim::loadMaterial("matte-paint"), sim::RigParams::realistic());
    return std::make_shared<test::StillScene>(renderer, test::stillPose(), test::stillLightMm());
  }();
  return scene;
}

// An empty desk: the target is not in view.
class EmptyScene final : public hal::SceneSource {
 public:
  EmptyScene() : light_(std::make_shared<hal::SceneLight>()) {
    const auto& k = vision::defaultSimulatedCamera().intrinsics;
    light_->widthPx = k.widthPx;
    light_->heightPx = k.heightPx;
    light_->ledRate.assign(std::size_t(k.widthPx) * k.heightPx * 3, 20.0f);
    light_->ambientRate.assign(std::size_t(k.widthPx) * k.heightPx * 3, 2.0f);
  }
  std::string id() const override { return "empty desk"; }
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<hal::SceneLight> light_;
};

constexpr std::int64_t kLedDelayUs = 40;  // the physical LED's light after the command

struct ModelRig {
  hal::FakeClock clock{5'000'000};
  std::shared_ptr<hal::LedTimeline> light = std::make_shared<hal::LedTimeline>();
  hal::TimelineLed led{std::make_unique<PlainLed>(), clock, light, kLedDelayUs};
  hal::SensorModel model;
  std::unique_ptr<hal::ModelCamera> camera;

  explicit ModelRig(hal::SensorModel m, std::shared_ptr<hal::SceneSource> scene = stillScene())
      : model(m) {
    model.realTime = false;
    model.holdSceneUntilStrobe = false;
    camera = std::make_unique<hal::ModelCamera>(std::move(scene), light, clock, model);
  }
  HardwareReport run(HardwareCheckOptions options = {}) {
    options.captureSeconds = 1.0;
    BackendInfo backend{{"model camera"}, Verdict::Warn, "none: the model delivers ISP output", ""};
    return runHardwareCheck(*camera, {}, led, clock, vision::defaultTarget(),
                            vision::defaultSimulatedCamera(), backend, options);
  }
};

const CheckItem& item(const HardwareReport& report, const std::string& name) {
  for (const CheckItem& i : report.items)
    if (i.name == name) return i;
  throw std::runtime_error("no item " + name + " in\n" + report.text());
}

TEST(HardwareCheck, ReportsTheModelsConfiguredTimingAndCurve) {
  hal::SensorModel sensor;  // the defaults: a camera module 3 at 1280 x 720 behind the Pi's ISP
  ModelRig rig(sensor);
  const HardwareReport report = rig.run();
  std::printf("%s\n", report.text().c_str());
  const MeasuredFigures& f = report.figures;
  const double readoutUs = sensor.lineTimeUs * 720;
  ASSERT_TRUE(f.readoutUs) << report.text();
  EXPECT_NEAR(*f.readoutUs, readoutUs, 0.1 * readoutUs);
  ASSERT_TRUE(f.ledOffsetUs);
  EXPECT_NEAR(*f.ledOffsetUs, double(kLedDelayUs), 0.1 * double(kLedDelayUs) + 10.0)
      << "10 us: a quarter of a line";
  ASSERT_TRUE(f.deliveryLatencyUs);
  EXPECT_NEAR(*f.deliveryLatencyUs, sensor.deliveryLatencyUs, 0.1 * sensor.deliveryLatencyUs);
  ASSERT_TRUE(f.framePeriodUs);
  EXPECT_NEAR(*f.framePeriodUs, sensor.framePeriodUs, 0.01 * sensor.framePeriodUs);
  EXPECT_EQ(f.framesDropped, 0);
  EXPECT_EQ(f.exposureLockDelayFrames, sensor.controlDelayFrames);
  ASSERT_TRUE(report.responseCurve);
  // The curve against the model's own, over the codes the bracket covered (above the darkest,
  // where 8-bit steps are large), as ratios to the brightest: what decoding uses.
  ASSERT_TRUE(report.responseRange);
  const auto [lowCode, highCode] = *report.responseRange;
  EXPECT_LT(lowCode, 20.0);
  EXPECT_GT(highCode, 200.0);
  EXPECT_LT(curveDistance(*report.responseCurve, sensor.tone, 20, highCode, highCode), 0.10);
  EXPECT_GT(*f.curveFromSrgb, 0.10) << "the IMX708 curve is not sRGB";
  EXPECT_EQ(item(report, "LED timing and readout").verdict, Verdict::Ok);
  EXPECT_EQ(item(report, "response curve").verdict, Verdict::Warn);  // not sRGB: says what to do
  ASSERT_EQ(report.configLines.size(), 2u);
  EXPECT_EQ(report.configLines[0].first, "readout_us");
  EXPECT_EQ(report.configLines[1].first, "led_guard_us");
  EXPECT_FALSE(rig.led.isOn()) << "the LED is left off";
}

}  // namespace
}  // namespace slicecap::hwcheck
