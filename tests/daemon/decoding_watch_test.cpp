// DecodingWatch: the status's warnings of a tone curve that changes from frame to frame and of a
// window channel taken below black, from the latest samples' figures.
#include "slicecap/daemon/decoding_watch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

namespace slicecap::daemon {
namespace {

capture::FrameOutcome sample(std::optional<double> blackReading, std::optional<Rgb> windowAtBlack) {
  capture::FrameOutcome outcome;
  outcome.kind = capture::FrameOutcome::Kind::Sample;
  outcome.measurement.blackReading = blackReading;
  outcome.measurement.windowAtBlack = windowAtBlack;
  return outcome;
}

// One LED block of "2 on, 2 off": the samples of its two LED-on frames (consecutive frames),
// then two LED-off frames the watch does not see.
std::uint64_t nextSequence = 100;
void noteBlock(DecodingWatch& watch, double first, double second, std::optional<Rgb> atBlack) {
  watch.note(sample(first, atBlack), nextSequence);
  watch.note(sample(second, atBlack), nextSequence + 1);
  nextSequence += 4;
}

TEST(DecodingWatch, WarnsOfACurveThatStepsEveryBlockAndOfAChannelBelowBlack) {
  DecodingWatch watch;
  EXPECT_FALSE(watch.view().blackReading || watch.view().windowAtBlack)
      << "nothing before the first sample";
  // One curve: the black reads the same within noise, stepping either way; the window's dark red
  // at black with noise (about half its pixels at code 0).
  for (int i = 0; i < 20; ++i)
    noteBlock(watch, 1.05, 1.05 * (i % 2 ? 1.03 : 0.97), Rgb{0.52, 0.02, 0.0});
  EXPECT_TRUE(watch.warnings().empty()) << watch.warnings().front();
  EXPECT_NEAR(*watch.view().blackReading, 1.05, 0.05 * 1.05);
  EXPECT_NEAR(*watch.view().blackReadingStep, 0.0, 0.01);
  EXPECT_EQ(watch.view().windowAtBlackChannel.value_or(""), "R");

  // A curve stretched from the frame before: the second frame of every block reads the black
  // 2 % higher than the first, within noise; and a colour matrix takes the window's green below
  // black in nearly every pixel. The latest 32 count.
  for (int i = 0; i < 32; ++i)
    noteBlock(watch, 1.0, 1.02 * (i % 3 ? 1.004 : 0.995), Rgb{0.3, i == 3 ? 0.1 : 0.97, 0.0});
  const std::vector<std::string> warnings = watch.warnings();
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NEAR(*watch.view().blackReadingStep, 0.02, 0.005);
  EXPECT_GT(*watch.view().blackReadingStepSigmas, DecodingWatch::kMinStepSigmas);
  EXPECT_NE(warnings[0].find("adaptive contrast"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("camera_raw"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("97.0 % of the window's G pixels"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[1].find("colour matrix"), std::string::npos) << warnings[1];

  watch.reset();
  EXPECT_FALSE(watch.view().blackReading) << "a new sweep run starts afresh";
}

TEST(DecodingWatch, ASmallStepWithinItsNoiseIsNotACurve) {
  // 2 % steps one way but the noise ten times that: not told apart from the noise.
  DecodingWatch watch;
  for (int i = 0; i < 32; ++i) noteBlock(watch, 1.0, 1.02 + (i % 2 ? 0.2 : -0.2), std::nullopt);
  ASSERT_TRUE(watch.view().blackReadingStepSigmas);
  EXPECT_LT(*watch.view().blackReadingStepSigmas, DecodingWatch::kMinStepSigmas);
  EXPECT_TRUE(watch.warnings().empty());
}

TEST(DecodingWatch, ALinearStreamIsNotWarnedAbout) {
  // RAW frames carry no window-at-black figure: their black reading's steps are not a curve's.
  DecodingWatch watch;
  for (int i = 0; i < 32; ++i) noteBlock(watch, 1.0, 1.05, std::nullopt);
  EXPECT_TRUE(watch.warnings().empty());
  EXPECT_TRUE(watch.view().blackReadingStep);
}

TEST(DecodingWatch, OnlySamplesOfConsecutiveFramesAreCompared) {
  // Frames apart (dropped, or another LED block's): the hand moved between them, not the curve.
  DecodingWatch watch;
  for (std::uint64_t i = 0; i < 40; ++i)
    watch.note(sample(i % 2 ? 1.0 : 1.2, Rgb{0.5, 0.5, 0.5}), 10 + 2 * i);
  EXPECT_FALSE(watch.view().blackReadingStep);
  EXPECT_TRUE(watch.warnings().empty());
}

TEST(DecodingWatch, AFewSamplesDoNotWarn) {
  DecodingWatch watch;
  for (std::size_t i = 0; i + 1 < DecodingWatch::kMinSamples / 2; ++i)
    noteBlock(watch, 1.0, 1.5, Rgb{1.0, 1.0, 1.0});
  EXPECT_TRUE(watch.warnings().empty());
}

// A sample whose window channels carry `light` (its LED light; 8-bit when `eightBit`).
capture::FrameOutcome lightSample(const Rgb& light, bool eightBit = true) {
  capture::FrameOutcome outcome = sample(std::nullopt, eightBit ? std::optional<Rgb>(Rgb{0.4, 0.5, 0.0})
                                                               : std::nullopt);
  outcome.measurement.windowLight = light;
  return outcome;
}

TEST(DecodingWatch, RefusesASweepWhoseWindowChannelTheLedDoesNotLight) {
  // Green pinned below black in 22 of 32 samples (the LED only adds light), a highlight's 10
  // above 0: refused, naming it.
  DecodingWatch watch;
  for (std::uint64_t i = 0; i < 32; ++i)
    watch.note(lightSample({0.02, i % 16 < 11 ? -0.0012 + 0.00002 * double(i % 5) : 0.004, 0.3}),
               10 + i);
  ASSERT_TRUE(watch.view().windowUnlit);
  EXPECT_EQ(*watch.view().windowUnlitChannel, "G");
  EXPECT_DOUBLE_EQ(*watch.view().windowUnlit, 22.0 / 32.0);
  EXPECT_LT(*watch.view().windowUnlitSigmas, -DecodingWatch::kMinBelowBlackSigmas);
  const std::optional<std::string> refusal = watch.refusal();
  ASSERT_TRUE(refusal);
  EXPECT_NE(refusal->find("G light from the LED sits below black over the latest 32 samples"),
            std::string::npos)
      << *refusal;
  EXPECT_NE(refusal->find("at or below 0 in 68.8 %"), std::string::npos) << *refusal;
  EXPECT_NE(refusal->find("tuning_file = auto"), std::string::npos) << *refusal;
  const std::vector<std::string> warnings = watch.warnings();
  EXPECT_NE(std::find(warnings.begin(), warnings.end(), *refusal), warnings.end())
      << "the status warns of it while the sweep runs";
  watch.reset();
  EXPECT_FALSE(watch.refusal()) << "a new sweep run starts afresh";
}

TEST(DecodingWatch, ADarkChannelTheLedLightsIsNotRefused) {
  // A dark channel read above 0 in most samples, noise taking it to or below 0 in a few (8 of
  // 32); and a channel at 0 in exactly half of them: not more than half.
  DecodingWatch dark, half;
  for (std::uint64_t i = 0; i < 32; ++i) {
    dark.note(lightSample({i % 4 == 0 ? -0.0005 : 0.002, 0.01, 0.3}), 10 + i);
    half.note(lightSample({0.02, i % 2 ? 0.0 : 0.0004, 0.3}), 10 + i);
  }
  EXPECT_DOUBLE_EQ(*dark.view().windowUnlit, 0.25);
  EXPECT_FALSE(dark.refusal());
  EXPECT_DOUBLE_EQ(*half.view().windowUnlit, 0.5);
  EXPECT_FALSE(half.refusal());
}

// An 8-bit HDR sweep: its short level is exposed for the highlight, so a dark channel sits in
// the noise of black there (at or below 0 in about half its samples, or all); the longest level,
// metered on the target, reads it lit. Two levels alternating: not refused.
TEST(DecodingWatch, AnHdrSweepsShortLevelInTheDarkIsNotADecodingLost) {
  DecodingWatch watch;
  for (std::uint64_t i = 0; i < 32; ++i) {
    capture::FrameOutcome outcome = lightSample({0.02, i % 2 ? -0.0004 : 0.01, 0.3});
    outcome.sample.emplace();
    outcome.sample->hdr.emplace();
    outcome.sample->hdr->exposureLevel = int(i % 2);
    watch.note(outcome, 10 + i);
  }
  EXPECT_FALSE(watch.refusal()) << *watch.refusal();
  ASSERT_TRUE(watch.view().windowUnlit);
  EXPECT_DOUBLE_EQ(*watch.view().windowUnlit, 0.0) << "the longest level's samples alone";
}

// Samples as a broken decoding gives them (the camera model's processed-isp frames, tests/daemon/
// decoding_watch_isp_test.cpp: green 35-110 standard errors below 0, its spread a twentieth of
// its distance from 0) against an honest dark channel: Gaussian noise around a mean of +0.2 to
// +1 standard deviations, a black material the LED barely lights. Over 2000 runs of each size:
// every broken one refused, whether a highlight's samples take a quarter of it above 0 or the
// clip pins it at exactly 0, and with 32 samples 95 % of those whose noise is as wide as their
// distance below 0; the honest ones refused at most 3 % of the time with 4 samples, 1.5 % with 8
// and 0.1 % with 32 (the measured rates are printed, beside those of the rule
// before, "more than half at or below 0": 13-21 % at +0.2).
TEST(DecodingWatch, TellsADecodingThatLostAChannelFromAnHonestDarkOne) {
  std::mt19937 random(44);
  std::normal_distribution<double> noise(0.0, 1.0);
  constexpr int kRuns = 2000;
  const auto watched = [&](std::size_t samples, const auto& light) {
    DecodingWatch watch;
    for (std::size_t i = 0; i < samples; ++i)
      watch.note(lightSample({0.02, light(i), 0.3}), 10 + i);
    return watch;
  };
  const auto run = [&](std::size_t samples, const auto& light) {
    return watched(samples, light).refusal().has_value();
  };
  for (const std::size_t samples : {std::size_t(4), std::size_t(8), std::size_t(32)}) {
    int pinned = 0, clipped = 0, wide = 0;
    for (int r = 0; r < kRuns; ++r) {
      // As the model's processed-isp diagonal 75/75 read: noise as wide as the distance below 0
      // (a third of the samples above 0), and a highlight's samples far above.
      wide += run(samples, [&](std::size_t i) {
        return i % 8 == 4 ? 0.6 * (1.0 + 0.03 * noise(random)) : 0.006 * (noise(random) - 1.0);
      });
      const double level = -0.0012 * (0.5 + 0.5 * double(r % 3));
      pinned += run(samples, [&](std::size_t i) {
        return i % 13 < 9 || samples < 8 ? level * (1.0 + 0.05 * noise(random))
                                         : 0.004 * (1.0 + noise(random) * 0.2);
      });
      clipped += run(samples, [&](std::size_t i) { return i % 4 == 3 ? -0.0001 : 0.0; });
    }
    EXPECT_EQ(pinned, kRuns) << samples;
    EXPECT_EQ(clipped, kRuns) << samples;
    if (samples == 32) {
      EXPECT_GE(wide, kRuns * 95 / 100) << samples;
    }
    for (const double meanSigmas : {0.2, 0.5, 1.0}) {
      int refused = 0, halfUnlit = 0;
      for (int r = 0; r < kRuns; ++r) {
        const DecodingWatch watch =
            watched(samples, [&](std::size_t) { return 0.002 * (meanSigmas + noise(random)); });
        refused += watch.refusal().has_value();
        halfUnlit += *watch.view().windowUnlit > 0.5;  // the rule before this one
      }
      const double rate = double(refused) / kRuns;
      std::printf("honest channel at +%.1f sigma, %zu samples: refused in %.2f %% of %d runs "
                  "(more than half at or below 0: %.1f %%)\n",
                  meanSigmas, samples, 100.0 * rate, kRuns, 100.0 * halfUnlit / kRuns);
      EXPECT_LE(rate, samples < 8 ? 0.03 : samples < 32 ? 0.015 : 0.001)
          << samples << " samples, +" << meanSigmas << " sigma";
    }
  }
}

// Whether the rule judged the run, and what it made of it, said as the status shows it: a RAW
// stream and a run of too few samples are not judged, and a broken one with
// refuse_broken_decoding = false is kept, said so.
TEST(DecodingWatch, SaysWhatTheRuleMakesOfTheRunInEachCase) {
  DecodingWatch none, linear, few, honest, broken;
  EXPECT_FALSE(none.unlitVerdict(RefusalPolicy::Refuse));
  for (std::uint64_t i = 0; i < 8; ++i) {
    linear.note(lightSample({0.02, -0.01, 0.3}, false), 10 + i);
    honest.note(lightSample({0.02, i % 2 ? 0.001 : 0.0005, 0.3}), 10 + i);
    broken.note(lightSample({0.02, -0.01 - 0.0001 * double(i % 3), 0.3}), 10 + i);
  }
  few.note(lightSample({0.02, -0.01, 0.3}), 10);
  EXPECT_EQ(linear.unlitVerdict(RefusalPolicy::Refuse).value_or(""),
            "not judged: a linear (RAW) stream keeps the light below black");
  EXPECT_EQ(few.unlitVerdict(RefusalPolicy::Refuse).value_or(""),
            "not judged yet: 1 of the 4 samples a judgement needs");
  EXPECT_EQ(honest.unlitVerdict(RefusalPolicy::Refuse).value_or(""),
            "kept: no channel sits below black");
  EXPECT_EQ(broken.unlitVerdict(RefusalPolicy::Refuse).value_or(""),
            "refused as the run ends: a channel sits below black");
  // The run over and refused (the sweep paused): said as done, not as to come.
  EXPECT_EQ(broken.unlitVerdict(RefusalPolicy::Refused).value_or(""),
            "refused: a channel sat below black; the run's samples and texture frames were set "
            "aside");
  EXPECT_EQ(broken.unlitVerdict(RefusalPolicy::WarnOnly).value_or(""),
            "a channel sits below black; kept, as refuse_broken_decoding = false");
  // Without a session nothing of the run was recorded, and nothing is refused: it says so.
  EXPECT_EQ(broken.unlitVerdict(RefusalPolicy::NoSession).value_or(""),
            "a channel sits below black; not refused: no session was open as the run began, so "
            "none of its samples were recorded");
}

TEST(DecodingWatch, ALinearStreamOrAFewSamplesAreNotRefused) {
  DecodingWatch linear, few;
  for (std::uint64_t i = 0; i < 32; ++i) linear.note(lightSample({0.02, -0.01, 0.3}, false), 10 + i);
  for (std::uint64_t i = 0; i + 1 < DecodingWatch::kMinRefusalSamples; ++i)
    few.note(lightSample({0.02, -0.01, 0.3}), 10 + i);
  EXPECT_FALSE(linear.refusal()) << "a RAW stream keeps what is below black";
  EXPECT_FALSE(few.refusal());
  EXPECT_DOUBLE_EQ(*few.view().windowUnlit, 1.0);
  few.note(lightSample({0.02, -0.01, 0.3}), 100);
  EXPECT_TRUE(few.refusal()) << DecodingWatch::kMinRefusalSamples << " samples are judged";
}

}  // namespace
}  // namespace slicecap::daemon
