// slicecap simulate: the recordings and truth it writes read back; bad input, an unknown material
// and a camera too large to render are named.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;

Result run(const std::vector<std::string>& args) { return test::runSlicecap(args); }

TEST(RigCommands, SimulateWritesARecordingWithTruth) {
  const auto dir = test::freshTempDir() / "sweep";
  const Result r = run({"simulate", "--material", "lambert:albedo=0.4", "-o", dir.string(),
                        "--frames", "2", "--ideal", "--slice", "diagonal", "--theta-i", "75"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  const io::Recording recording = io::readRecording(dir);
  ASSERT_EQ(recording.frames.size(), 2u);
  EXPECT_EQ(recording.slice->id, (SliceId{SliceKind::Diagonal, {75, 30}}));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "truth.json"));
  // A recording is never overwritten.
  const Result again =
      run({"simulate", "--material", "lambert", "-o", dir.string(), "--frames", "2"});
  EXPECT_EQ(again.code, kExitFailure);
  EXPECT_NE(again.err.find(dir.string()), std::string::npos) << again.err;
}

TEST(RigCommands, SimulateSessionWritesTheEightSlices) {
  const auto dir = test::freshTempDir() / "session";
  const Result r = run({"simulate", "--material", "lambert:albedo=0.4", "--session", dir.string(),
                        "--frames", "2", "--ideal", "--encoding", "linear16"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  int recordings = 0;
  for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
    for (const ElevationPair& pair : kMeasuredPairs) {
      const std::string name = std::string(toString(kind)) + "-" + std::to_string(pair.thetaIDeg) +
                               "-" + std::to_string(pair.thetaVDeg);
      const io::Recording recording = io::readRecording(dir / name);
      EXPECT_EQ(recording.slice->id, (SliceId{kind, pair})) << name;
      EXPECT_EQ(recording.encoding, PixelEncoding::Linear16);
      EXPECT_EQ(recording.frames.size(), 2u);
      ++recordings;
    }
  }
  EXPECT_EQ(recordings, 8);
}

TEST(RigCommands, SimulateNamesBadInput) {
  const auto dir = test::freshTempDir();
  const Result material =
      run({"simulate", "--material", "ggx:ax=7", "-o", (dir / "a").string(), "--frames", "2"});
  EXPECT_EQ(material.code, kExitUsage);
  EXPECT_NE(material.err.find("ax"), std::string::npos) << material.err;
  EXPECT_EQ(run({"simulate", "--material", "lambert"}).code, kExitUsage)
      << "neither -o nor --session";
  EXPECT_EQ(run({"simulate", "--material", "lambert", "-o", "x", "--theta-i", "30.5"}).code,
            kExitUsage);
  EXPECT_EQ(run({"simulate", "--material", "lambert", "-o", "x", "--slice", "sideways"}).code,
            kExitUsage);
}

TEST(RigCommands, AnUnknownMaterialIsBadUsageInSimulateAsInGenerate) {
  const auto dir = test::freshTempDir();
  const Result generate = run({"generate", "no-such-material", "-o", (dir / "t.exr").string()});
  const Result simulate = run({"simulate", "--material", "no-such-material", "-o",
                               (dir / "rec").string(), "--frames", "2"});
  EXPECT_EQ(generate.code, kExitUsage) << generate.err;
  EXPECT_EQ(simulate.code, kExitUsage) << simulate.err;
  EXPECT_NE(simulate.err.find("--material: unknown material 'no-such-material'"), std::string::npos)
      << simulate.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "rec"));
  // A table that cannot be read is a failure naming the file, as every reader's.
  const Result table = run({"simulate", "--material", (dir / "missing.exr").string(), "-o",
                            (dir / "rec").string(), "--frames", "2"});
  EXPECT_EQ(table.code, kExitFailure) << table.err;
  EXPECT_NE(table.err.find("missing.exr"), std::string::npos) << table.err;
}

TEST(RigCommands, SimulateRefusesACameraTooLargeToRenderNamingItsFile) {
  // A 100000 x 100000 camera was accepted and its first frame failed with a bare bad_alloc.
  const auto dir = test::freshTempDir();
  nlohmann::json camera = io::cameraToJson(vision::defaultSimulatedCamera());
  camera["width_px"] = 100000;
  camera["height_px"] = 100000;
  const auto cameraFile = dir / "huge-camera.json";
  std::ofstream(cameraFile) << camera.dump();
  const Result r = run({"simulate", "--material", "lambert:albedo=0.5", "-o",
                        (dir / "rec").string(), "--frames", "2", "--camera", cameraFile.string()});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("huge-camera.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("width_px"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("16384"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "rec"));
}

}  // namespace
}  // namespace slicecap::cli
