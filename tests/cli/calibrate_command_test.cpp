// `slicecap calibrate` end to end: simulated sweeps at three elevations to a camera file that a
// recording then refers to.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;
const auto run = test::runSlicecap;

TEST(CalibrateCommand, RecoversTheVirtualRigsCameraAndARecordingUsesIt) {
  const auto dir = test::freshTempDir();
  std::vector<std::string> recordings;
  for (const char* thetaV : {"30", "50", "75"}) {
    recordings.push_back((dir / (std::string("v") + thetaV)).string());
    ASSERT_EQ(run({"simulate", "--material", "lambert:albedo=0.5,0.4,0.3", "-o", recordings.back(),
                   "--theta-v", thetaV, "--frames", "8", "--seed", "3"})
                  .code,
              kExitOk);
  }
  const auto camera = (dir / "camera.json").string();
  const Result r = run({"calibrate", recordings[0], recordings[1], recordings[2], "-o", camera});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.out.find("RMS reprojection error"), std::string::npos) << r.out;

  const vision::CameraModel truth = io::readRecording(recordings[0]).camera;
  const nlohmann::json file = io::readJsonFile(camera);
  const vision::CameraModel fitted = io::cameraFromJson(file, camera);
  EXPECT_NEAR(fitted.intrinsics.fxPx, truth.intrinsics.fxPx, 0.005 * truth.intrinsics.fxPx);
  EXPECT_NEAR(fitted.intrinsics.fyPx, truth.intrinsics.fyPx, 0.005 * truth.intrinsics.fyPx);
  // The principal point is the least certain (the target stays near the image centre): within a
  // few pixels, and within three of the reported standard deviations.
  const auto& sigma = file["calibration"]["sigma"];
  EXPECT_NEAR(fitted.intrinsics.cxPx, truth.intrinsics.cxPx,
              std::min(8.0, 3.0 * sigma["cx_px"].get<double>()));
  EXPECT_NEAR(fitted.intrinsics.cyPx, truth.intrinsics.cyPx,
              std::min(8.0, 3.0 * sigma["cy_px"].get<double>()));
  EXPECT_LT(file["calibration"]["rms_reprojection_px"].get<double>(), 0.3);
  EXPECT_GT(sigma["fx_px"].get<double>(), 0.0);

  // A recording refers to the session's calibration by a path outside its own directory.
  io::Recording recording = io::readRecording(recordings[0]);
  recording.calibrationFile = "../camera.json";
  io::writeRecordingManifest(recordings[0], recording);
  EXPECT_EQ(io::readRecording(recordings[0]).camera, fitted);
}

TEST(CalibrateCommand, BadInputIsAClearError) {
  const auto dir = test::freshTempDir();
  const Result missing = run({"calibrate", (dir / "nothing").string(), "-o", "c.json"});
  EXPECT_EQ(missing.code, kExitFailure);
  EXPECT_NE(missing.err.find("nothing"), std::string::npos) << missing.err;
  const auto recording = (dir / "few").string();
  ASSERT_EQ(run({"simulate", "--material", "lambert:albedo=0.5", "-o", recording, "--frames", "2",
                 "--ideal"})
                .code,
            kExitOk);
  const Result few = run({"calibrate", recording, "-o", (dir / "c.json").string()});
  EXPECT_EQ(few.code, kExitFailure);
  EXPECT_NE(few.err.find("need 4"), std::string::npos) << few.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "c.json"));
  EXPECT_EQ(run({"calibrate", recording, "-o", "c.json", "--max-views", "2"}).code, kExitUsage);
}

}  // namespace
}  // namespace slicecap::cli
