// The sweep-start metering on a simulated camera: it reaches the target from too dark and from
// clipped, stops at the camera's range, and waits for each change to reach the frames.
#include "slicecap/daemon/exposure_meter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace slicecap::daemon {
namespace {

// 100 x 100 linear frame: `background` everywhere, `highlight` on a 10 x 10 block (1 %).
hal::Frame frameWith(double background, double highlight) {
  hal::Frame frame;
  frame.encoding = PixelEncoding::Linear16;
  frame.image = {100, 100, 3, 16, std::vector<std::uint16_t>(100 * 100 * 3)};
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x)
      for (int c = 0; c < 3; ++c)
        frame.image.at(x, y, c) =
            std::uint16_t(std::min(1.0, x < 10 && y < 10 ? highlight : background) * 65535.0 + 0.5);
  return frame;
}

TEST(ExposureMeter, TheBrightLevelIsAHighPercentileOfTheLargestChannel) {
  const hal::Frame frame = frameWith(0.2, 0.9);
  EXPECT_NEAR(brightLevel(frame, 0.005), 0.9, 1e-4);  // inside the 1 % block
  EXPECT_NEAR(brightLevel(frame, 0.05), 0.2, 1e-4);   // beyond it
  hal::Frame srgb;
  srgb.encoding = PixelEncoding::Srgb8;
  srgb.image = {4, 4, 3, 8, std::vector<std::uint16_t>(4 * 4 * 3, 0)};
  srgb.image.at(0, 0, 1) = 188;  // one channel of one sampled pixel: sRGB 188 is linear 0.50
  EXPECT_NEAR(brightLevel(srgb, 0.25), 0.5, 0.01);
  EXPECT_EQ(brightLevel(hal::Frame{}, 0.005), 0.0);
}

// A camera whose bright level is `levelAt10ms` x exposure / 10 ms, clipped at 1, with a range.
// A lock reaches the sensor `delayFrames` frames late; each frame reports its own exposure
// (`reportsExposure`) or, as a camera that does not apply locks at all, the auto exposure forever.
struct SimulatedCamera {
  double levelAt10ms;
  double minUs = 100.0, maxUs = 100'000.0;
  int delayFrames = 0;
  bool appliesLocks = true;
  // Before the first lock: its auto exposure, and the level it gives then (LED off, another
  // gain); a negative level: as at any exposure.
  double autoExposureUs = 30'000.0;
  double autoLevel = -1.0;
  hal::ExposureSetting lock(const hal::ExposureSetting& s) const {
    return {std::clamp(s.exposureUs, minUs, maxUs), s.gain.value_or(1.0)};
  }
  hal::Frame frameAt(double exposureUs, std::uint32_t locks = 1) const {
    const bool auto_ = locks == 0 && autoLevel >= 0.0;
    hal::Frame frame = frameWith(0.0, auto_ ? autoLevel : levelAt10ms * exposureUs / 10'000.0);
    frame.metadata.exposureUs = exposureUs;
    frame.metadata.exposureLocks = locks;
    return frame;
  }
};

// Runs the metering to its end; returns the frames it took.
int meter(ExposureMeter& m, const SimulatedCamera& camera, hal::ExposureSetting& final) {
  hal::ExposureSetting current = camera.lock(m.firstSetting(std::nullopt));
  m.accepted(current);
  double onSensorUs = camera.autoExposureUs;
  std::uint32_t applied = 0;
  std::vector<std::pair<int, double>> pending{{camera.delayFrames, current.exposureUs}};
  for (int frame = 1; frame <= 200; ++frame) {
    while (camera.appliesLocks && !pending.empty() && pending.front().first < frame) {
      onSensorUs = pending.front().second;
      ++applied;
      pending.erase(pending.begin());
    }
    const ExposureMeter::Step step = m.onFrame(camera.frameAt(onSensorUs, applied));
    if (step.kind == ExposureMeter::Step::Kind::Done) {
      final = step.setting;
      return frame;
    }
    if (step.kind == ExposureMeter::Step::Kind::Lock) {
      current = camera.lock(step.setting);
      m.accepted(current);
      pending.push_back({frame + camera.delayFrames, current.exposureUs});
    }
  }
  ADD_FAILURE() << "the metering never ended";
  return -1;
}

TEST(ExposureMeter, ADarkSceneIsBroughtUpToTheTarget) {
  const ExposureMeterParams params;
  ExposureMeter m(params);
  hal::ExposureSetting final;
  const SimulatedCamera camera{0.12};  // 29 ms needed
  const int frames = meter(m, camera, final);
  EXPECT_TRUE(m.onTarget()) << m.summary();
  const double level = 0.12 * final.exposureUs / 10'000.0;
  EXPECT_LE(level, params.targetLevel * params.tolerance);
  EXPECT_GE(level, params.targetLevel / params.tolerance);
  EXPECT_EQ(final.gain, 1.0);
  // Each change waits settleFrames frames, then one frame is measured.
  EXPECT_EQ(frames, (m.steps() + 1) * (params.settleFrames + 1));
  EXPECT_NE(m.summary().find("exposure locked at"), std::string::npos);
}

TEST(ExposureMeter, AClippedSceneStepsDownUntilItIsOnTarget) {
  ExposureMeter m;
  hal::ExposureSetting final;
  meter(m, SimulatedCamera{5.0}, final);  // clipped at the start exposure
  EXPECT_TRUE(m.onTarget()) << m.summary();
  EXPECT_NEAR(5.0 * final.exposureUs / 10'000.0, 0.35, 0.35 * 0.25);
  EXPECT_GE(m.steps(), 2);  // the first step only knew "clipped"
}

TEST(ExposureMeter, TheCamerasRangeEndsTheMeteringOffTheTarget) {
  ExposureMeter m;
  hal::ExposureSetting final;
  SimulatedCamera camera{0.001};
  camera.maxUs = 30'000.0;
  meter(m, camera, final);
  EXPECT_FALSE(m.onTarget());
  EXPECT_EQ(final.exposureUs, 30'000.0);
  EXPECT_NE(m.summary().find("off the target"), std::string::npos);
}

TEST(ExposureMeter, FramesExposedBeforeAChangeReachedTheSensorAreNotMeasured) {
  // Measured by frame count alone, a lock 6 or more frames late was metered on the frames of the
  // setting before and locked far off the target, called on target.
  for (const int delay : {0, 3, 6, 9, 14}) {
    SCOPED_TRACE(delay);
    ExposureMeter m;
    hal::ExposureSetting final;
    SimulatedCamera camera{0.12};
    camera.delayFrames = delay;
    meter(m, camera, final);
    EXPECT_TRUE(m.onTarget()) << m.summary();
    EXPECT_NEAR(0.12 * final.exposureUs / 10'000.0, 0.35, 0.35 * 0.25) << m.summary();
  }
}

TEST(ExposureMeter, AFrameFromBeforeTheLockIsNotMeasuredEvenAtTheLockedExposure) {
  // A Pi's auto exposure sits at 10 ms, the start value, with its gain raised and the LED still
  // off: matched by exposure alone such a frame was metered at 0.33, "on target" after 0 steps,
  // and the sweep ran near clipping.
  ExposureMeter m;
  hal::ExposureSetting final;
  SimulatedCamera camera{0.95};
  camera.delayFrames = 7;
  camera.autoExposureUs = 10'000.0;
  camera.autoLevel = 0.33;
  meter(m, camera, final);
  EXPECT_TRUE(m.onTarget()) << m.summary();
  EXPECT_GE(m.steps(), 1) << m.summary();
  EXPECT_NEAR(0.95 * final.exposureUs / 10'000.0, 0.35, 0.35 * 0.25) << m.summary();
}

TEST(ExposureMeter, ACameraThatNeverAppliesTheLockEndsOffTheTargetSayingSo) {
  ExposureMeter m;
  hal::ExposureSetting final;
  SimulatedCamera camera{0.05};
  camera.appliesLocks = false;
  const int frames = meter(m, camera, final);
  EXPECT_EQ(frames, ExposureMeterParams{}.maxFramesPerChange);
  EXPECT_FALSE(m.onTarget());
  EXPECT_NE(m.summary().find("not measured"), std::string::npos) << m.summary();
  EXPECT_NE(m.summary().find("the camera's frames still reported 30000 us 30 frames after the "
                             "change"),
            std::string::npos)
      << m.summary();
}

TEST(ExposureMeter, TheExposureStopsAtOneFrameAt30FpsSayingSo) {
  // Longer would lower the frame rate and blur the moving rig; the camera would allow it.
  ExposureMeter m;
  hal::ExposureSetting final;
  meter(m, SimulatedCamera{0.02}, final);  // 175 ms needed
  EXPECT_FALSE(m.onTarget());
  EXPECT_DOUBLE_EQ(final.exposureUs, ExposureMeterParams{}.maxExposureUs);
  EXPECT_NE(m.summary().find("the exposure limit (33333 us"), std::string::npos) << m.summary();
}

TEST(ExposureMeter, ARefusedStepEndsTheMeteringAtTheSettingBefore) {
  ExposureMeter m;
  m.accepted({10'000.0, 1.0});
  m.refused("fake refused a manual gain");
  const ExposureMeter::Step step = m.onFrame(SimulatedCamera{0.05}.frameAt(10'000.0));
  EXPECT_EQ(step.kind, ExposureMeter::Step::Kind::Done);
  EXPECT_EQ(step.setting.exposureUs, 10'000.0);
  EXPECT_FALSE(m.onTarget());
  EXPECT_NE(m.summary().find("the camera refused the next step (fake refused a manual gain)"),
            std::string::npos)
      << m.summary();
}

TEST(ExposureMeter, TheConfiguredGainIsKept) {
  ExposureMeter m;
  EXPECT_EQ(m.firstSetting(4.0).gain, 4.0);
  EXPECT_FALSE(m.firstSetting(std::nullopt).gain);
}

}  // namespace
}  // namespace slicecap::daemon
