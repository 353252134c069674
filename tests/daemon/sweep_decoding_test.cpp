// The sweep's decoding on the camera model: the bracket the daemon takes after the metering
// recovers the model's IMX708 curve; a bracket without the target, or a camera that refuses the
// lock, falls back to sRGB with a warning naming the camera; a linear stream takes no bracket.
#include "slicecap/daemon/sweep_decoding.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../support/bracket_rig.hpp"
#include "../support/curve_error.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/daemon/config.hpp"
#include "slicecap/sim/material.hpp"

namespace slicecap::daemon {
namespace {


std::shared_ptr<const sim::FrameRenderer> renderer() {
  static const auto r = std::make_shared<const sim::FrameRenderer>(
      vision::defaultSimulatedCamera(), vision::defaultTarget(), sim::loadMaterial("matte-paint"),
      sim::RigParams::ideal());
  return r;
}

// As the daemon's frame loop: the metered setting locked, then the bracket's steps against the
// camera until Done; the frames after it must be at the metered exposure again.
struct BracketRun {
  SweepDecoding decoding;
  double exposureAfterUs = 0.0;
};
BracketRun runBracket(test::BracketRig& rig, double meteredUs, bool refuseSecondLock = false) {
  const hal::ExposureSetting metered{meteredUs, 1.0};
  std::uint32_t locks = 0;
  if (rig.camera->lockExposure(metered).locked) ++locks;
  ResponseBracket bracket(metered, locks);
  EXPECT_TRUE(rig.camera->lockExposure(bracket.firstSetting()).locked);
  bracket.accepted();
  for (int n = 0; n < 400; ++n) {
    hal::CaptureResult result = rig.camera->nextFrame(std::chrono::milliseconds(1000));
    if (result.status != hal::CaptureResult::Status::Frame) continue;
    const ResponseBracket::Step step = bracket.onFrame(*result.frame);
    if (step.kind == ResponseBracket::Step::Kind::Lock) {
      if (refuseSecondLock) {
        bracket.refused("model: manual gain refused");
        continue;
      }
      EXPECT_TRUE(rig.camera->lockExposure(step.setting).locked);
      bracket.accepted();
    } else if (step.kind == ResponseBracket::Step::Kind::Done) {
      BracketRun run;
      run.exposureAfterUs = result.frame->metadata.exposureUs;
      run.decoding = decodingFromBracket(std::move(bracket.frames()), bracket.failure(),
                                         {renderer()->target(), renderer()->camera()}, "model:rig");
      return run;
    }
  }
  ADD_FAILURE() << "the bracket never ended";
  return {};
}

TEST(SweepDecoding, TheBracketOnTheCameraModelRecoversItsCurveWithinTwoPercent) {
  auto scene = std::make_shared<test::StillScene>(renderer(), test::stillPose(), test::stillLightMm());
  // The IMX708's tuning curve, colour gains, noise, and one curve for the bracket to recover:
  // with a Pi's adaptive contrast (the model's default) the curve changes from frame to frame
  // and the fit misses by far more than 2 % (issue 44; refusing such a fit is the response
  // gate's work), so this test takes the fixed ISP.
  hal::SensorModel model;
  model.isp = hal::fixedModelIsp();
  test::BracketRig rig(scene, model);
  const double meteredUs = rig.meteredExposureUs();
  const BracketRun run = runBracket(rig, meteredUs);
  const SweepDecoding& d = run.decoding;
  ASSERT_EQ(d.decoding.kind, io::RecordedDecoding::Kind::MeasuredCurve) << d.warning;
  EXPECT_TRUE(d.warning.empty()) << d.warning;
  EXPECT_EQ(d.bracketFrames.size(), 8u);
  EXPECT_NE(d.note.find("measured curve"), std::string::npos) << d.note;
  // The sweep goes on at the metered exposure.
  EXPECT_NEAR(run.exposureAfterUs, meteredUs, 0.05 * meteredUs);
  // Issue 27's goal over the target's white-to-black range at the metered exposure
  // (docs/linear-light.md: linear 0.0068 .. 0.33).
  ASSERT_TRUE(d.decoding.curve);
  const double error = test::largestRelativeError(*d.decoding.curve, ToneCurve::imx708Tuning(), 0.0068, 0.33);
  EXPECT_LT(error, 0.02) << d.note;
  std::printf("[ bracket ] %s; curve error over linear 0.0068..0.33: %.2f %% relative to the white\n",
              d.note.c_str(), 100 * error);
  // sRGB is far off the same range: the test can tell the two apart.
  EXPECT_GT(test::largestRelativeError(ToneCurve::srgb(), ToneCurve::imx708Tuning(), 0.0068, 0.33), 0.1);
  // The session's record says it, with the curve.
  const nlohmann::json json = toJson(d, "model:rig");
  EXPECT_EQ(json["decoding"], "measured-curve");
  EXPECT_EQ(json["bracket_frames"], 8);
  EXPECT_GT(json["curve"]["points"].size(), 16u);
}

TEST(SweepDecoding, ABracketWithoutTheTargetInViewFallsBackToSrgbSayingSo) {
  // The camera looks 400 mm past the target: paper and table, no marker.
  const vision::Pose away =
      vision::lookAtPose({0.0, 600.0, 300.0}, {0.0, 1000.0, 0.0}, {0, 0, 1});
  auto scene = std::make_shared<test::StillScene>(renderer(), away, test::stillLightMm());
  test::BracketRig rig(scene, {});
  const SweepDecoding d = runBracket(rig, 8000.0).decoding;
  EXPECT_EQ(d.decoding.kind, io::RecordedDecoding::Kind::Srgb);
  EXPECT_FALSE(d.decoding.curve);
  EXPECT_NE(d.warning.find("model:rig"), std::string::npos) << d.warning;
  EXPECT_NE(d.warning.find("target was not found"), std::string::npos) << d.warning;
  EXPECT_NE(d.warning.find("decodes its 8-bit frames as sRGB"), std::string::npos) << d.warning;
  EXPECT_NE(d.warning.find("decoding = srgb"), std::string::npos) << d.warning;
  EXPECT_EQ(d.bracketFrames.size(), 8u);  // kept: record_frames writes them for a desktop look
}

TEST(SweepDecoding, ACameraThatRefusesABracketLockFallsBackToSrgbSayingSo) {
  auto scene = std::make_shared<test::StillScene>(renderer(), test::stillPose(), test::stillLightMm());
  test::BracketRig rig(scene, {});
  const SweepDecoding d = runBracket(rig, rig.meteredExposureUs(), true).decoding;
  EXPECT_EQ(d.decoding.kind, io::RecordedDecoding::Kind::Srgb);
  EXPECT_NE(d.warning.find("camera model:rig: no response bracket: the camera refused"),
            std::string::npos)
      << d.warning;
}

TEST(SweepDecoding, ALinearStreamTakesNoBracketAndSrgbIsStated) {
  const SweepDecoding linear = decodingWithoutBracket(PixelEncoding::Linear16, DecodingMode::Auto, "raw", "");
  EXPECT_EQ(linear.decoding.kind, io::RecordedDecoding::Kind::Linear);
  EXPECT_TRUE(linear.warning.empty());
  const SweepDecoding asked = decodingWithoutBracket(PixelEncoding::Srgb8, DecodingMode::Srgb, "uvc", "");
  EXPECT_EQ(asked.decoding.kind, io::RecordedDecoding::Kind::Srgb);
  EXPECT_TRUE(asked.warning.empty()) << "asked for: no warning";
  const SweepDecoding fallback =
      decodingWithoutBracket(PixelEncoding::Srgb8, DecodingMode::Auto, "uvc", "no lock");
  EXPECT_NE(fallback.warning.find("camera uvc: no lock"), std::string::npos) << fallback.warning;
}

TEST(DecodingMode, NamesAndRefusesValues) {
  for (const DecodingMode mode : {DecodingMode::Auto, DecodingMode::MeasuredCurve, DecodingMode::Srgb})
    EXPECT_EQ(decodingModeFromString(toString(mode)), mode);
  try {
    decodingModeFromString("raw");
    FAIL() << "no error";
  } catch (const daemon::ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("'raw'"), std::string::npos);
  }
}

// A sweep run's decoding check is added to its decoding record, and the session's export reads
// each recorded warning back with the slice it came from; a record without a check adds none.
TEST(SweepDecoding, TheDecodingChecksWarningsAreKeptInTheSessionAndReadBack) {
  const std::filesystem::path session = test::freshTempDir();
  std::filesystem::create_directories(session / kDecodingFolder);
  SweepDecoding decided;
  decided.note = "measured curve";
  const std::filesystem::path checked = session / kDecodingFolder / "axial-30-30.json";
  io::writeJsonFileAtomically(checked, toJson(decided, "model"));
  io::writeJsonFileAtomically(session / kDecodingFolder / "axial-30-75.json", toJson(decided, "model"));
  recordDecodingCheck(checked,
                      control::DecodingCheckView{1.01, 0.05, 6.0, "G", 0.97, "G", 0.9, 0.0, -30.0,
                                                 -45.0, "refused as the run ends", "R", 0.012, 5.0},
                      {"decoding: 97.0 % of the window's G pixels are at code 0"});
  const nlohmann::json record = io::readJsonFile(checked);
  EXPECT_EQ(record["note"], "measured curve") << "the record keeps what it said";
  EXPECT_EQ(record["check"]["window_at_black_channel"], "G");
  EXPECT_EQ(record["check"]["window_unlit"], 0.9);
  EXPECT_EQ(record["check"]["window_unlit_sigmas"], -30.0);
  EXPECT_EQ(record["check"]["window_unlit_mean_sigmas"], -45.0);
  EXPECT_EQ(record["check"]["window_step_channel"], "R");
  const std::vector<std::string> warnings = recordedDecodingWarnings(session);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "sweep axial-30-30: decoding: 97.0 % of the window's G pixels are at code 0");
  EXPECT_THROW(recordDecodingCheck(session / "missing.json", {}, {}), std::exception);
}

}  // namespace
}  // namespace slicecap::daemon
