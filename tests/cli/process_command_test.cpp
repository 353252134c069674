// `slicecap process` end to end: a simulated sweep to the slice CSV, the report and the summary.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/cli_runner.hpp"
#include "../support/png_claiming_size.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/slice_csv.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;
const auto run = test::runSlicecap;

TEST(ProcessCommand, WritesSlicesReportAndSummary) {
  const auto dir = test::freshTempDir();
  const auto recording = (dir / "diagonal-30-30").string();
  ASSERT_EQ(run({"simulate", "--material", "lambert:albedo=0.5,0.4,0.3", "-o", recording, "--slice",
                 "diagonal", "--frames", "6", "--ideal"})
                .code,
            kExitOk);
  const auto csv = (dir / "s.csv").string(), report = (dir / "r.json").string();
  const Result r = run({"process", recording, "-o", csv, "--report", report});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("diagonal 30/30"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3 of 24 bins"), std::string::npos) << r.err;
  const SliceSet slices = io::readSliceCsv(csv);
  const Slice* slice = slices.find({SliceKind::Diagonal, {30, 30}});
  ASSERT_NE(slice, nullptr);
  ASSERT_EQ(slice->samples.size(), 3u);
  for (const SliceSample& s : slice->samples)  // Lambertian: albedo / pi in every direction
    EXPECT_NEAR(s.value[0], 0.5 / M_PI, 0.01 * 0.5 / M_PI);
  nlohmann::json j;
  std::ifstream(report) >> j;
  EXPECT_EQ(j["recordings"][0]["frames"].size(), 6u);
  // The bins to pass again: a Lambertian surface has no peak to miss, so only empty bins, none
  // of them one a frame filled (the 3 filled bins' cells reach a neighbour at most).
  const nlohmann::json& passAgain = j["recordings"][0]["pass_again"];
  EXPECT_GE(passAgain.size(), 15u);
  EXPECT_LE(passAgain.size(), 21u);
  for (const auto& bin : passAgain) {
    EXPECT_EQ(bin["reason"], "empty");
    EXPECT_DOUBLE_EQ(bin["azimuth_deg"].get<double>(), 15.0 * bin["bin"].get<int>());
    EXPECT_TRUE(j["recordings"][0]["bins"][bin["bin"].get<int>()]["frames"].empty()) << bin;
  }
  // Too few frames (3) to tell texture: the cells as read, said in the report and on stderr.
  EXPECT_EQ(j["recordings"][0]["cell_texture"]["action"], "as read");
  EXPECT_EQ(j["recordings"][0]["cell_texture"]["frames_used"], 3);
  EXPECT_NE(r.err.find("cells: as read (texture not measured: 3 frames)"), std::string::npos)
      << r.err;
  EXPECT_EQ(j["recordings"][0]["frames"][1]["outcome"], "ambient");
  // The first frame has no earlier pose: the whole frame was searched.
  EXPECT_EQ(j["recordings"][0]["frames"][0]["detection"]["tracked"], false);
  for (const auto& frame : j["recordings"][0]["frames"])
    if (frame["outcome"] == "sample") {
      EXPECT_TRUE(frame["detection"].is_object()) << frame.dump();
    }

  // The cells' reading of the same frames: each bin's value from the cell nearest its centre, at
  // that cell's own directions, the irradiance read at the cell: Lambertian everywhere again.
  const auto cellsCsv = (dir / "cells.csv").string();
  ASSERT_EQ(run({"process", recording, "-o", csv, "--cell-slices", cellsCsv}).code, kExitOk);
  const Slice* cells = io::readSliceCsv(cellsCsv).find({SliceKind::Diagonal, {30, 30}});
  ASSERT_NE(cells, nullptr);
  ASSERT_GE(cells->samples.size(), 3u);
  for (const SliceSample& s : cells->samples)
    EXPECT_NEAR(s.value[0], 0.5 / M_PI, 0.03 * 0.5 / M_PI);
  EXPECT_EQ(run({"process", recording, "-o", csv, "--cell-slices", csv}).code, kExitUsage);
  const Result badTexture = run({"process", recording, "-o", csv, "--cell-texture", "mean"});
  EXPECT_EQ(badTexture.code, kExitUsage);
  EXPECT_NE(badTexture.err.find("--cell-texture: 'mean'"), std::string::npos) << badTexture.err;
  for (const char* every : {"1e-20", "0", "16", "nan", "3deg"}) {
    const Result badEvery = run({"process", recording, "-o", csv, "--cell-points-every", every});
    EXPECT_EQ(badEvery.code, kExitUsage) << every;
    EXPECT_NE(badEvery.err.find("--cell-points-every: '" + std::string(every) + "'"),
              std::string::npos) << badEvery.err;
  }

  // The same slice twice, a directory without a recording: usage error / failure naming it.
  EXPECT_EQ(run({"process", recording, recording, "-o", csv}).code, kExitUsage);
  EXPECT_EQ(run({"process", recording, "-o", csv, "--ambient", "sideways"}).code, kExitUsage);
  // The live loop's one-sided room-light term, offline: the same samples without room light.
  const Result previous = run({"process", recording, "-o", csv, "--ambient", "previous"});
  ASSERT_EQ(previous.code, kExitOk) << previous.err;
  EXPECT_NE(previous.err.find("3 of 24 bins"), std::string::npos) << previous.err;
  const Result missing = run({"process", (dir / "nothing").string(), "-o", csv});
  EXPECT_EQ(missing.code, kExitFailure);
  EXPECT_NE(missing.err.find("nothing"), std::string::npos) << missing.err;
}

// The LED on in every frame (simulate --no-led-alternation, slicecapd's led_alternate = false):
// every frame was "no_ambient_frame". Offline follows the recording: no room-light term, said.
TEST(ProcessCommand, ARecordingWithTheLedAlwaysOnIsProcessedWithoutARoomLightTerm) {
  const auto dir = test::freshTempDir();
  const auto recording = (dir / "axial-30-30").string();
  ASSERT_EQ(run({"simulate", "--material", "lambert:albedo=0.5,0.4,0.3", "-o", recording,
                 "--frames", "4", "--ideal", "--no-led-alternation"})
                .code,
            kExitOk);
  for (const io::RecordedFrame& frame : io::readRecording(recording).frames)
    ASSERT_TRUE(frame.ledOn);
  const auto csv = (dir / "s.csv").string(), report = (dir / "r.json").string();
  const Result r = run({"process", recording, "-o", csv, "--report", report});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_EQ(r.err.find("no_ambient_frame"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("4 of 24 bins, 4 samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("room light not subtracted"), std::string::npos) << r.err;
  nlohmann::json j;
  std::ifstream(report) >> j;
  EXPECT_NE(j["recordings"][0]["room_light"].get<std::string>().find("no LED-off frame"),
            std::string::npos)
      << j["recordings"][0]["room_light"];
  // The room light stays in the samples, but it lights a Lambertian window and the paper alike:
  // about albedo / pi still (the room light is ~3 % of the LED's).
  const SliceSet slices = io::readSliceCsv(csv);
  ASSERT_EQ(slices.slices().size(), 1u);
  for (const SliceSample& s : slices.slices()[0].samples)
    EXPECT_NEAR(s.value[0], 0.5 / M_PI, 0.05 * 0.5 / M_PI);
}

TEST(ProcessCommand, AFrameWhoseHeaderClaimsTooManyPixelsIsABadFrame) {
  // A 100-byte PNG claiming 100000 x 100000 ended the whole run with a bare std::bad_alloc.
  const auto dir = test::freshTempDir();
  const auto recording = dir / "diagonal-30-30";
  ASSERT_EQ(run({"simulate", "--material", "lambert:albedo=0.5", "-o", recording.string(),
                 "--slice", "diagonal", "--frames", "4", "--ideal"})
                .code,
            kExitOk);
  const io::RecordedFrame bomb = io::readRecording(recording).frames[2];
  test::writePngClaimingSize(io::framePath(recording, bomb), 100000, 100000);
  const auto report = (dir / "r.json").string();
  const Result r =
      run({"process", recording.string(), "-o", (dir / "s.csv").string(), "--report", report});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("1 bad_frame"), std::string::npos) << r.err;
  nlohmann::json j;
  std::ifstream(report) >> j;
  const auto& frame = j["recordings"][0]["frames"][2];
  EXPECT_EQ(frame["reason"], "bad_frame") << frame.dump();
  EXPECT_NE(frame["detail"].get<std::string>().find(bomb.file), std::string::npos) << frame.dump();
}

TEST(ProcessCommand, DecimationOutsideItsRangeIsAUsageError) {
  // `--decimation 360` crashed the AprilTag library; the options are checked before any input is
  // read, so no recording is needed to see the usage error.
  const auto dir = test::freshTempDir();
  const std::string missing = (dir / "nothing").string(), out = (dir / "out").string();
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"process", missing, "-o", out + ".csv"},
        std::vector<std::string>{"capture-offline", missing, "-o", out + ".exr"},
        std::vector<std::string>{"btf", missing, "-o", out}}) {
    for (const char* decimation : {"360", "0.5", "17"}) {
      std::vector<std::string> args = command;
      args.insert(args.end(), {"--decimation", decimation});
      SCOPED_TRACE(command[0] + " --decimation " + decimation);
      const Result r = run(args);
      EXPECT_EQ(r.code, kExitUsage) << r.err;
      EXPECT_NE(r.err.find("--decimation must be in 1..16"), std::string::npos) << r.err;
    }
  }
}

// Two ideal 6-frame recordings (3 LED-on frames each) under dir/session.
std::vector<std::filesystem::path> twoRecordings(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> recordings;
  for (const char* theta : {"30", "75"}) {
    recordings.push_back(dir / "session" / (std::string("diagonal-") + theta));
    EXPECT_EQ(run({"simulate", "--material", "lambert:albedo=0.5", "-o", recordings.back().string(),
                   "--slice", "diagonal", "--theta-i", theta, "--theta-v", theta, "--frames", "6",
                   "--ideal"})
                  .code,
              kExitOk);
  }
  return recordings;
}

TEST(ProcessCommand, NoSampleFromAnyRecordingFailsNamingThemAndKeepsTheReport) {
  // It exited 0 and wrote a slice CSV with a header and no sample, which every reader refuses.
  const auto dir = test::freshTempDir();
  const auto recordings = twoRecordings(dir);
  const auto csv = dir / "s.csv", report = dir / "r.json";
  Result r = run({"process", recordings[0].string(), recordings[1].string(), "-o", csv.string(),
                  "--report", report.string(), "--min-markers", "1000"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("no recording gave a sample"), std::string::npos) << r.err;
  for (const auto& recording : recordings)
    EXPECT_NE(r.err.find(recording.string() + " (diagonal "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rejected 3 too_few_markers"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(csv));
  nlohmann::json j;
  std::ifstream(report) >> j;
  EXPECT_EQ(j["recordings"].size(), 2u) << "the diagnosis is kept";

  // capture-offline alike: neither the EXR nor --slices, the report written.
  const auto exr = dir / "o.exr", report2 = dir / "r2.json";
  r = run({"capture-offline", (dir / "session").string(), "-o", exr.string(), "--slices",
           csv.string(), "--report", report2.string(), "--min-markers", "1000"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("no recording gave a sample"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rejected 3 too_few_markers"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(csv));
  EXPECT_FALSE(std::filesystem::exists(exr));
  EXPECT_TRUE(std::filesystem::exists(report2));
}

TEST(ProcessCommand, ARecordingWithoutSamplesAmongOthersIsNamedInAWarning) {
  const auto dir = test::freshTempDir();
  const auto recordings = twoRecordings(dir);
  for (const io::RecordedFrame& frame : io::readRecording(recordings[1]).frames)
    if (frame.ledOn) std::ofstream(io::framePath(recordings[1], frame)) << "not a PNG";
  const auto csv = dir / "s.csv";
  const Result r =
      run({"process", recordings[0].string(), recordings[1].string(), "-o", csv.string()});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("warning: no sample from " + recordings[1].string() +
                       " (diagonal 75/75): rejected 3 bad_frame"),
            std::string::npos)
      << r.err;
  const SliceSet slices = io::readSliceCsv(csv);
  EXPECT_EQ(slices.sampleCount(), 3u) << "the other recording's samples are kept";
}

TEST(ProcessCommand, ASessionLackingSlicesNamesThemWithTheirSweepsAndExportsWithThePrior) {
  const auto dir = test::freshTempDir();
  twoRecordings(dir);  // diagonal 30/30 and 75/75 of the eight
  const auto exr = dir / "o.exr";
  const Result r = run({"capture-offline", (dir / "session").string(), "-o", exr.string()});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  for (const char* slice : {"axial 30/30: slicecap sweep start axial 30 30",
                            "diagonal 30/75: slicecap sweep start diagonal 30 75",
                            "axial 75/75: slicecap sweep start axial 75 75"})
    EXPECT_NE(r.err.find(slice), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("diagonal 75/75:"), std::string::npos) << r.err;
  io::ExrAttributes attributes;
  io::readAbrdfExr(exr, &attributes);
  EXPECT_EQ(attributes.at("method"), "prior");
}

TEST(ProcessCommand, BadMethodsAndRecordingsAreRefusedBeforeAnyFrameIsProcessed) {
  // --method and a broken recording.json were found only after every frame before them had
  // been processed (minutes on a real session).
  const auto dir = test::freshTempDir();
  const auto recordings = twoRecordings(dir);
  const auto session = (dir / "session").string(), exr = (dir / "o.exr").string();
  const std::string processed = "of 24 bins";  // each recording's summary line
  Result r = run({"capture-offline", session, "-o", exr, "--method", "nosuch"});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.err.find("unknown method 'nosuch'"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(processed), std::string::npos) << r.err;

  // The last recording (in sorted order) without a slice, then with a bad field.
  const auto manifest = recordings[1] / io::kRecordingManifest;
  nlohmann::json j;
  std::ifstream(manifest) >> j;
  const nlohmann::json good = j;
  j.erase("slice");
  std::ofstream(manifest) << j.dump();
  r = run({"capture-offline", session, "-o", exr});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find(recordings[1].string() + ": recording.json has no slice"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find(processed), std::string::npos) << r.err;
  j = good;
  j["frames"][0]["exposure_us"] = -5;
  std::ofstream(manifest) << j.dump();
  r = run({"capture-offline", session, "-o", exr});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("exposure_us"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(processed), std::string::npos) << r.err;

  // The same slice twice.
  std::ofstream(manifest) << good.dump();
  r = run(
      {"process", recordings[0].string(), recordings[0].string(), "-o", (dir / "s.csv").string()});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_EQ(r.err.find(processed), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(exr));
}

}  // namespace
}  // namespace slicecap::cli
