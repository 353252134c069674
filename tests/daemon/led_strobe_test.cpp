// LedStrobe against the camera model: frames labelled from the LED's timeline over their rows
// match what the LED really did; the strobe before it (label at delivery) does not.
#include "slicecap/daemon/led_strobe.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "slicecap/capture/led_gate.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "../support/plain_led.hpp"
#include "slicecap/hal/model_camera.hpp"

namespace slicecap::daemon {
namespace {

constexpr int kWidth = 16, kHeight = 720;

class DarkScene final : public hal::SceneSource {
 public:
  DarkScene() : light_(std::make_shared<hal::SceneLight>()) {
    light_->widthPx = kWidth;
    light_->heightPx = kHeight;
    light_->ledRate.assign(std::size_t(kWidth) * kHeight * 3, 10.0f);
    light_->ambientRate.assign(std::size_t(kWidth) * kHeight * 3, 1.0f);
  }
  std::string id() const override { return "flat"; }
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t) override { return light_; }

 private:
  std::shared_ptr<hal::SceneLight> light_;
};

// A frame loop as the daemon's: frames arrive from the model camera, each takes the pipeline
// `processingUs` (every `slowEvery`-th frame `slowUs`), and a planned switch fires when the loop
// is free at or after its time.
struct Harness {
  hal::FakeClock clock{10'000'000};
  std::shared_ptr<hal::LedTimeline> light = std::make_shared<hal::LedTimeline>();
  std::shared_ptr<hal::LedTimeline> commanded = std::make_shared<hal::LedTimeline>();
  std::unique_ptr<hal::TimelineLed> led;
  std::unique_ptr<hal::ModelCamera> camera;
  capture::RowSpan rows{240, 480};
  double processingUs = 9000.0, slowUs = 70000.0;
  int slowEvery = 11;
  // Spoils each frame's metadata before the strobe sees it (a camera that stamps nothing).
  std::function<void(hal::FrameMetadata&)> spoil;

  struct Tally {
    int frames = 0, clean = 0, mislabelled = 0;
    std::string warning;
  };

  explicit Harness(hal::SensorModel model, double exposureUs) {
    model.realTime = false;
    auto physical = std::make_unique<hal::TimelineLed>(std::make_unique<test::PlainLed>(), clock, light, 40);
    led = std::make_unique<hal::TimelineLed>(std::move(physical), clock, commanded);
    camera = std::make_unique<hal::ModelCamera>(std::make_shared<DarkScene>(), light, clock, model);
    hal::CameraConfig config;
    config.widthPx = kWidth;
    config.heightPx = kHeight;
    config.exposureUs = exposureUs;
    camera->configure(config);
    camera->start();
  }

  // Did the label the capture reads (over `rows`) say what the LED did over those rows?
  void judge(const hal::Frame& frame, Tally& tally) const {
    const std::optional<hal::FrameTruth> truth = camera->truth(frame.metadata.sequence);
    ASSERT_TRUE(truth);
    ++tally.frames;
    const hal::LedExposure::State state = capture::ledStateOver(frame, rows);
    if (state == hal::LedExposure::State::Mixed) return;  // rejected: led_transition
    ++tally.clean;
    const float wanted = state == hal::LedExposure::State::On ? 1.0f : 0.0f;
    for (int row = rows.first; row <= rows.last; ++row)
      if (std::abs(truth->rowOnFraction[row] - wanted) > 1e-6f) {
        ++tally.mislabelled;
        return;
      }
  }

  void process(int index) { clock.advanceUs(std::int64_t(index % slowEvery == 0 ? slowUs : processingUs)); }

  Tally runStrobe(StrobeSettings settings, int frames) {
    LedStrobe strobe(settings, *led, commanded, camera->id());
    led->set(true);
    strobe.noteRows(rows);
    Tally tally;
    std::optional<PlannedSwitch> pending;
    for (int index = 0; tally.frames < frames;) {
      if (pending && pending->atUs <= clock.nowUs()) {
        strobe.fire(*pending);  // late when the frame before took long: as the daemon's loop
        pending.reset();
        continue;
      }
      const auto untilSwitch = pending ? std::chrono::milliseconds((pending->atUs - clock.nowUs()) / 1000)
                                       : std::chrono::milliseconds(1000);
      hal::CaptureResult result = camera->nextFrame(untilSwitch);
      if (result.status != hal::CaptureResult::Status::Frame) {
        if (pending) clock.sleepUntilUs(pending->atUs);
        continue;
      }
      hal::Frame& frame = *result.frame;
      if (spoil) spoil(frame.metadata);
      strobe.label(frame, clock.nowUs());
      judge(frame, tally);
      process(index++);
      if (!pending) pending = strobe.plan(clock.nowUs() + 1000);  // as the daemon: kept once planned
    }
    EXPECT_EQ(strobe.stats().framesDelivered, std::uint64_t(frames));
    tally.warning = strobe.stats().warning;
    return tally;
  }

  // The strobe before the camera model: a frame is labelled with the LED's state when it arrives,
  // and the LED flips for "the next" frame.
  Tally runLabelAtDelivery(int frames) {
    Tally tally;
    for (int index = 0; tally.frames < frames;) {
      hal::CaptureResult result = camera->nextFrame(std::chrono::milliseconds(1000));
      if (result.status != hal::CaptureResult::Status::Frame) continue;
      hal::Frame& frame = *result.frame;
      frame.metadata.ledOn = led->isOn();
      led->set(!led->isOn());
      judge(frame, tally);
      process(index++);
    }
    return tally;
  }
};

TEST(LedStrobe, TheStrobeBeforeTheCameraModelMislabelsFrames) {
  Harness harness({}, 8000.0);
  const Harness::Tally tally = harness.runLabelAtDelivery(120);
  EXPECT_GT(tally.mislabelled, 20) << "of " << tally.frames;
}

TEST(LedStrobe, NoFrameIsLabelledOtherwiseThanTheLedShoneOnItsRows) {
  Harness harness({}, 8000.0);
  const Harness::Tally tally = harness.runStrobe({}, 300);
  EXPECT_EQ(tally.mislabelled, 0);
  // 2 on, 2 off with an 8 ms exposure: the rows of interest leave room for every switch, so
  // only the switches a slow frame delayed cost a frame.
  EXPECT_GT(tally.clean, 0.8 * tally.frames) << tally.clean << " of " << tally.frames;
}

// A switch fired late (a busy loop) can leave the switch back already past when the next one is
// planned: the strobe then plans the next switch away from the state the LED is in, never one to
// the same state, which would hold the LED for a whole extra pattern (the daemon's camera model
// ran a live HDR sweep with the LED off for seconds so).
TEST(LedStrobe, AfterALateSwitchTheNextOneIsAwayFromTheLedsState) {
  Harness harness({}, 8000.0);
  LedStrobe strobe({}, *harness.led, harness.commanded, harness.camera->id());
  harness.led->set(true);
  strobe.noteRows(harness.rows);
  for (int i = 0; i < 6; ++i) {  // the frame timing
    hal::CaptureResult result = harness.camera->nextFrame(std::chrono::milliseconds(1000));
    ASSERT_EQ(result.status, hal::CaptureResult::Status::Frame);
    strobe.label(*result.frame, harness.clock.nowUs());
  }
  const std::optional<PlannedSwitch> fired = strobe.plan(harness.clock.nowUs());
  ASSERT_TRUE(fired);
  strobe.fire(*fired);
  for (std::int64_t laterUs = 0; laterUs < 300'000; laterUs += 5'000) {
    const std::optional<PlannedSwitch> next = strobe.plan(fired->atUs + laterUs);
    ASSERT_TRUE(next) << laterUs;
    EXPECT_NE(next->on, fired->on) << "planned from " << laterUs << " us after the switch";
  }
}

TEST(LedStrobe, ALongExposureCostsFramesButNeverALabel) {
  Harness harness({}, 30000.0);
  StrobeSettings settings;
  settings.framesPerState = 3;
  const Harness::Tally tally = harness.runStrobe(settings, 300);
  EXPECT_EQ(tally.mislabelled, 0);
  EXPECT_GT(tally.clean, 0.4 * tally.frames) << tally.clean << " of " << tally.frames;
  EXPECT_LT(tally.clean, tally.frames);
}

TEST(LedStrobe, ACameraThatDoesNotSayItsExposureIsJudgedConservativelyAndSaysSo) {
  hal::SensorModel model;
  model.reportsExposure = false;
  Harness harness(model, 8000.0);
  StrobeSettings settings;
  settings.framesPerState = 6;
  const Harness::Tally tally = harness.runStrobe(settings, 240);
  EXPECT_EQ(tally.mislabelled, 0);
  EXPECT_GT(tally.clean, 0);
  EXPECT_NE(tally.warning.find("does not report when its frames were exposed"), std::string::npos)
      << tally.warning;
  EXPECT_NE(tally.warning.find("model:flat"), std::string::npos) << tally.warning;
}

// A camera whose frames carry no timestamp (0) or the same one over and over: the strobe says so,
// naming the camera, times frames by their arrival with a wide window and longer LED blocks, and
// still never mislabels a frame.
TEST(LedStrobe, ACameraWithoutTimestampsFallsBackToArrivalTimesAndSaysSo) {
  for (const std::int64_t stamp : {std::int64_t(0), std::int64_t(123456)}) {
    SCOPED_TRACE(stamp);
    Harness harness({}, 8000.0);
    harness.spoil = [stamp](hal::FrameMetadata& m) {
      m.timestampUs = stamp;
      m.exposureStartUs.reset();
    };
    const Harness::Tally tally = harness.runStrobe({}, 240);
    EXPECT_EQ(tally.mislabelled, 0);
    EXPECT_GT(tally.clean, 0.3 * tally.frames) << tally.clean << " of " << tally.frames;
    EXPECT_LT(tally.clean, tally.frames);
    EXPECT_NE(tally.warning.find("model:flat reports no usable frame timestamps"), std::string::npos)
        << tally.warning;
    EXPECT_NE(tally.warning.find("holds each state for 12 frames"), std::string::npos) << tally.warning;
  }
}

TEST(LedStrobe, UntimedFramesGetIncreasingArrivalTimestamps) {
  Harness harness({}, 8000.0);
  LedStrobe strobe({}, *harness.led, harness.commanded, "cam");
  std::int64_t previous = 0;
  for (int i = 0; i < 10; ++i) {
    hal::CaptureResult result = harness.camera->nextFrame(std::chrono::milliseconds(1000));
    ASSERT_EQ(result.status, hal::CaptureResult::Status::Frame);
    result.frame->metadata.timestampUs = 0;
    strobe.label(*result.frame, harness.clock.nowUs());
    EXPECT_GT(result.frame->metadata.timestampUs, previous);
    EXPECT_LE(result.frame->metadata.timestampUs, harness.clock.nowUs());
    previous = result.frame->metadata.timestampUs;
  }
  EXPECT_TRUE(strobe.untimed());
  EXPECT_EQ(strobe.pattern(), "12 on, 12 off");
}

TEST(LedStrobe, CountsDroppedFramesFromSequenceGaps) {
  Harness harness({}, 8000.0);
  harness.slowUs = 250000.0;  // a stall longer than four frames' buffers
  harness.slowEvery = 20;
  LedStrobe strobe({}, *harness.led, harness.commanded, "cam");
  for (int i = 0; i < 60; ++i) {
    hal::CaptureResult result = harness.camera->nextFrame(std::chrono::milliseconds(1000));
    ASSERT_EQ(result.status, hal::CaptureResult::Status::Frame);
    strobe.label(*result.frame, harness.clock.nowUs());
    harness.process(i);
  }
  EXPECT_EQ(strobe.stats().framesDropped, harness.camera->framesDropped());
  EXPECT_GT(strobe.stats().framesDropped, 0u);
}

TEST(LedStrobe, PlansASwitchEvenWhenTheLatestFrameIsLongPast) {
  // A loop seconds behind the camera (frames queued behind slow ones): the next switch is still
  // one in the future, not none.
  Harness harness({}, 8000.0);
  LedStrobe strobe({}, *harness.led, harness.commanded, "cam");
  for (int i = 0; i < 3; ++i) {
    hal::CaptureResult result = harness.camera->nextFrame(std::chrono::milliseconds(1000));
    ASSERT_EQ(result.status, hal::CaptureResult::Status::Frame);
    strobe.label(*result.frame, harness.clock.nowUs());
  }
  const std::int64_t laterUs = harness.clock.nowUs() + 5'000'000;
  const std::optional<PlannedSwitch> planned = strobe.plan(laterUs);
  ASSERT_TRUE(planned);
  EXPECT_GE(planned->atUs, laterUs);
  EXPECT_LT(planned->atUs, laterUs + 5 * 33334);
}

TEST(StrobeSettings, RefusesValuesOutOfRangeNamingTheKey) {
  StrobeSettings settings;
  settings.framesPerState = 0;
  std::string why;
  EXPECT_FALSE(settings.isValid(&why));
  EXPECT_NE(why.find("led_frames_per_state"), std::string::npos);
  settings.framesPerState = 2;
  settings.readoutUs = -3.0;
  EXPECT_FALSE(settings.isValid(&why));
  EXPECT_NE(why.find("readout_us"), std::string::npos);
}

}  // namespace
}  // namespace slicecap::daemon
