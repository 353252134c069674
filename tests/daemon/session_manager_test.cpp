// The session state machine behind the protocol: lifecycle, refusals, restart after a kill,
// storage failure mid-sweep, reconstruct and export.
#include "slicecap/daemon/session_manager.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "../support/file_size_limit.hpp"
#include "../support/manager_reply.hpp"
#include "../support/sweep_sample.hpp"
#include "../support/test_support.hpp"
#include "../support/window_cells_sweep.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/slice_csv.hpp"

namespace slicecap::daemon {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};
const SliceId kAxial3075{SliceKind::Axial, {30, 75}};
const SliceId kDiagonal3030{SliceKind::Diagonal, {30, 30}};

using test::sampleAt;

// Stands in for the method registry: the mean sample value everywhere, or a failure.
Abrdf meanOfSlices(const SliceSet& slices, const std::string& method) {
  if (method == "needs-more") throw std::runtime_error("missing slices: diagonal 75/75");
  if (method == "one-slice" && slices.slices().size() > 1)
    throw std::runtime_error("reads one slice only");
  double sum = 0;
  for (const Slice& slice : slices.slices())
    for (const SliceSample& sample : slice.samples)
      sum += sample.value.r();
  Abrdf table;
  const auto mean = static_cast<float>(sum / double(slices.sampleCount()));
  for (int light = 0; light < bonn::kDirectionCount; ++light)
    for (int view = 0; view < bonn::kDirectionCount; ++view)
      table.set(light, view, Rgb::gray(mean));
  return table;
}

using test::ok;

control::ProtocolError refused(SessionManager& manager, const control::Command& command) {
  auto reply = manager.handle(command);
  if (auto* error = std::get_if<control::ProtocolError>(&reply)) return *error;
  ADD_FAILURE() << control::commandName(command) << " was accepted: " << std::get<json>(reply).dump();
  return {};
}

// A sample whose HDR reading the journal would refuse (not finite) costs that frame, counted as
// bad_frame; the sweep goes on and keeps its other samples.
TEST(SessionManager, ASampleTheJournalRefusesIsABadFrameNotAStoppedSweep) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"brushed steel", std::string("steel")});
  ok(manager, control::SweepStart{kDiagonal3030});
  EXPECT_TRUE(manager.acceptSample(test::hdrSampleAt(15.0, 2.0, 1.0, 0, 1)));
  capture::FrameSample broken = test::hdrSampleAt(30.0, 2.0, 1.0, 1, 2);
  broken.hdr->cells[3].radiance = Rgb{std::nan(""), 1.0, 1.0};
  EXPECT_FALSE(manager.acceptSample(broken));
  EXPECT_TRUE(manager.acceptSample(test::hdrSampleAt(45.0, 2.0, 1.0, 0, 3)));
  const json status = manager.status();
  EXPECT_EQ(status["sweep"]["state"], "capturing");
  EXPECT_EQ(status["sweep"]["samples"], 2);
  EXPECT_EQ(status["sweep"]["rejected"]["bad_frame"], 1);
}

TEST(SessionManager, WalksAPersonThroughASweep) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  EXPECT_EQ(manager.status()["next"], "slicecap session new MATERIAL");
  const json session = ok(manager, control::SessionNew{"red felt", std::string("felt")});
  EXPECT_EQ(session["id"], "felt");
  EXPECT_EQ(manager.status()["next"], "slicecap sweep start diagonal 30 30");
  EXPECT_FALSE(manager.capturing());

  ok(manager, control::SweepStart{kDiagonal3030});
  EXPECT_TRUE(manager.capturing());
  for (int k = 0; k < 10; ++k)
    EXPECT_TRUE(manager.acceptSample(sampleAt(k * 15.0, 0.5, k)));
  manager.rejectFrame(capture::RejectReason::TooFewMarkers);
  manager.rejectFrame(capture::RejectReason::TooFewMarkers);
  manager.rejectFrame(capture::RejectReason::ElevationOff);
  manager.noteViewElevationErrorDeg(-2.5);
  const json status = manager.status();
  EXPECT_EQ(status["sweep"]["state"], "capturing");
  EXPECT_EQ(status["sweep"]["bins_filled"], 10);
  EXPECT_EQ(status["sweep"]["bins"].size(), 24u);
  EXPECT_EQ(status["sweep"]["rejected"]["too_few_markers"], 2);
  EXPECT_EQ(status["sweep"]["rejected"]["elevation_off"], 1);
  EXPECT_DOUBLE_EQ(status["sweep"]["view_elevation_error_deg"].get<double>(), -2.5);
  EXPECT_THAT(status["next"].get<std::string>(), HasSubstr("10 of 24 bins"));

  const json stopped = ok(manager, control::SweepStop{});
  EXPECT_EQ(stopped["state"], "stopped");
  EXPECT_FALSE(manager.capturing());
  EXPECT_FALSE(manager.acceptSample(sampleAt(0, 0.5, 99)));  // no sweep: nothing stored
  EXPECT_EQ(manager.status()["session"]["samples"], 10);
  // A hand-held sweep seldom fills all 24 bins: a slice with samples counts as swept.
  EXPECT_EQ(manager.status()["next"], "slicecap sweep start diagonal 75 75");
}

// A run ends at a pause: accepted_this_run counts the run that ended while paused, and the
// continued sweep's new run from 0 (the slice's samples go on counting all of them).
TEST(SessionManager, AcceptedThisRunRestartsWithEachRun) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"red felt", std::string("felt")});
  ok(manager, control::SweepStart{kDiagonal3030});
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(manager.acceptSample(sampleAt(k * 15.0, 0.5, k)));
  manager.pauseSweep("the camera's recording has ended");
  EXPECT_EQ(manager.status()["sweep"]["accepted_this_run"], 3);
  const json continued = ok(manager, control::SweepStart{kDiagonal3030});
  EXPECT_EQ(continued["accepted_this_run"], 0);
  EXPECT_TRUE(manager.acceptSample(sampleAt(60.0, 0.5, 3)));
  const json status = manager.status();
  EXPECT_EQ(status["sweep"]["accepted_this_run"], 1);
  EXPECT_EQ(status["sweep"]["samples"], 4);
}

TEST(SessionManager, NamesTheBinsToPassAgainDuringAndAfterASweep) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  ok(manager, control::SweepStart{kAxial3030});
  for (int k = 0; k < 10; ++k) {
    if (k == 4) continue;  // a bin the hand went over too fast
    ASSERT_TRUE(manager.acceptSample(sampleAt(k * 15.0, 0.5, k)));
  }
  json status = manager.status();
  // While it runs: the gap at 60 deg it left behind, not the bins from 150 deg still ahead.
  ASSERT_EQ(status["pass_again"].size(), 1u);
  EXPECT_EQ(status["pass_again"][0]["slice"]["name"], toString(kAxial3030));
  EXPECT_EQ(status["pass_again"][0]["azimuth_deg"], 60.0);
  EXPECT_EQ(status["pass_again"][0]["reason"], "empty");
  EXPECT_THAT(status["next"].get<std::string>(),
              testing::EndsWith("9 of 24 bins filled; pass again slowly over 60 deg (empty)"));
  // The answer is kept between requests, and worked out again once the bins change.
  EXPECT_EQ(manager.status()["pass_again"], status["pass_again"]);
  ASSERT_TRUE(manager.acceptSample(sampleAt(60.0, 0.5, 4)));
  EXPECT_FALSE(manager.status().contains("pass_again")) << "the gap filled";
  ASSERT_TRUE(manager.acceptSample(sampleAt(150.0, 0.5, 10)));
  ASSERT_TRUE(manager.acceptSample(sampleAt(180.0, 0.5, 12)));
  EXPECT_EQ(manager.status()["pass_again"].size(), 1u) << "165 deg, passed over";
  ok(manager, control::SweepStop{});
  status = manager.status();
  EXPECT_EQ(status["pass_again"].size(), 12u) << "165 deg, and the 11 bins of 195-345 deg";
  EXPECT_THAT(status["next"].get<std::string>(),
              testing::EndsWith("; to pass again slowly: `slicecap sweep start axial 30 30` over "
                                "165 deg (empty)"));
}

TEST(SessionManager, JudgesTheWindowsTextureWhileASweepRunsAndShowsTheVerdictOnceItStops) {
  // A plain material under a weave whose bright thread lies under the window's edge cells on the
  // side ahead of the sweep (3 x the others): read as they are, the cells before the 86-94 deg
  // gap rise toward 90 deg like a sharp peak's. The running sweep's texture is judged as its
  // frames come, so it is not named.
  const SliceId diagonal7575{SliceKind::Diagonal, {75, 75}};
  const test::Profile flat = [](double) { return 1.0; };
  // The thread: the window's cells that, in the last frame before the gap (84 deg), lie within
  // 1.2 deg of the nearest to the 90 deg bin centre's directions (the rule's distance).
  const capture::FrameSample probe =
      test::placedDiagonalFrameAt(84, flat, 0, [](int, int) { return 1.0; });
  const AzimuthPair centre = slicePoint(SliceKind::Diagonal, 90);
  std::array<double, 64> distanceDeg{};
  for (std::size_t k = 0; k < 64; ++k) {
    const capture::CellSample& cell = probe.cells->cells[k];
    distanceDeg[k] = std::hypot(angleBetweenDeg(cell.light, {75, centre.phiIDeg}),
                                angleBetweenDeg(cell.view, {75, centre.phiVDeg}));
  }
  const double nearestDeg = *std::min_element(distanceDeg.begin(), distanceDeg.end());
  const auto thread = [&](int i, int j) {
    return distanceDeg[std::size_t(8 * i + j)] <= nearestDeg + 1.2 ? 3.0 : 1.0;
  };
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"woven", std::string("woven")});
  ok(manager, control::SweepStart{diagonal7575});
  std::uint64_t index = 0;
  for (double p = 0; p <= 180; p += 3.0) {
    if (p > 86 && p < 94) continue;
    const capture::FrameSample frame = test::placedDiagonalFrameAt(p, flat, ++index, thread);
    ASSERT_TRUE(manager.acceptSample(frame));
    for (const control::PassAgainView& bin : manager.statusView().passAgain)
      EXPECT_NE(bin.reason, "peak_not_reached") << bin.azimuthDeg << " deg, frame " << index;
  }
  EXPECT_TRUE(manager.statusView().cellTextures.empty()) << "the running sweep's is not final";
  ok(manager, control::SweepStop{});
  const control::StatusView status = manager.statusView();
  ASSERT_EQ(status.cellTextures.size(), 1u);
  const control::CellTextureView& verdict = status.cellTextures.front();
  EXPECT_EQ(verdict.slice, diagonal7575);
  EXPECT_NE(verdict.action, "as read");
  ASSERT_TRUE(verdict.spreadPercent);
  EXPECT_GT(*verdict.spreadPercent, 10.0);
  EXPECT_THAT(verdict.reason, HasSubstr("texture (spread"));
  EXPECT_EQ(manager.status()["cell_texture"][0]["action"], verdict.action);
}

TEST(SessionManager, RefusesWhatTheStateDoesNotAllow) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  EXPECT_EQ(refused(manager, control::SweepStart{kAxial3030}).code, control::ErrorCode::Conflict);
  EXPECT_EQ(refused(manager, control::SessionShow{"nobody"}).code, control::ErrorCode::NotFound);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  EXPECT_EQ(refused(manager, control::SessionNew{"again", std::string("felt")}).code, control::ErrorCode::Conflict);
  ok(manager, control::SweepStart{kAxial3030});
  EXPECT_THAT(refused(manager, control::SweepStart{kAxial3075}).message, HasSubstr("axial 30/30"));
  EXPECT_EQ(refused(manager, control::SessionNew{"other", std::nullopt}).code, control::ErrorCode::Conflict);
  EXPECT_EQ(refused(manager, control::SessionDelete{"felt"}).code, control::ErrorCode::Conflict);
  EXPECT_EQ(refused(manager, control::Reconstruct{std::nullopt, "b"}).code, control::ErrorCode::Conflict);
  EXPECT_EQ(refused(manager, control::SweepRedo{kAxial3075}).code, control::ErrorCode::Conflict);
  ok(manager, control::SweepStop{});
  EXPECT_EQ(refused(manager, control::SweepStop{}).code, control::ErrorCode::Conflict);
  ok(manager, control::SessionDelete{"felt"});
  EXPECT_TRUE(manager.status()["session"].is_null());
}

TEST(SessionManager, AKilledDaemonComesBackToItsSweepWithEverySample) {
  const auto root = test::freshTempDir();
  {
    SessionManager manager(root, meanOfSlices);
    ok(manager, control::SessionNew{"felt", std::string("felt")});
    ok(manager, control::SweepStart{kAxial3030});
    for (int k = 0; k < 7; ++k)
      ASSERT_TRUE(manager.acceptSample(sampleAt(k * 15.0, 0.5, k)));
    // No stop: the object goes away as a killed daemon's state would.
  }
  SessionManager restarted(root, meanOfSlices);
  const json status = restarted.status();
  EXPECT_EQ(status["session"]["id"], "felt");
  EXPECT_EQ(status["sweep"]["state"], "paused");
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(), HasSubstr("interrupted"));
  EXPECT_EQ(status["sweep"]["samples"], 7);
  EXPECT_FALSE(restarted.capturing());
  EXPECT_EQ(refused(restarted, control::SweepStart{kAxial3075}).code, control::ErrorCode::Conflict);
  ok(restarted, control::SweepStart{kAxial3030});
  EXPECT_TRUE(restarted.capturing());
  EXPECT_TRUE(restarted.acceptSample(sampleAt(7 * 15.0, 0.5, 7)));
  EXPECT_EQ(restarted.status()["sweep"]["samples"], 8);
}

TEST(SessionManager, RedoDiscardsOnlyThatSlice) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  ok(manager, control::SweepStart{kAxial3030});
  for (int k = 0; k < 5; ++k)
    manager.acceptSample(sampleAt(k * 15.0, 0.5, k));
  ok(manager, control::SweepStop{});
  ok(manager, control::SweepStart{kAxial3075});
  for (int k = 0; k < 3; ++k)
    manager.acceptSample(sampleAt(k * 15.0, 0.5, k));
  ok(manager, control::SweepStop{});
  const json redone = ok(manager, control::SweepRedo{kAxial3030});
  EXPECT_EQ(redone["samples"], 0);
  EXPECT_TRUE(manager.capturing());
  EXPECT_EQ(manager.status()["session"]["samples"], 3);
}

TEST(SessionManager, ACameraFailurePausesTheSweepAndStartContinuesIt) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  ok(manager, control::SweepStart{kAxial3030});
  manager.acceptSample(sampleAt(0, 0.5, 0));
  manager.pauseSweep("camera error: frame 12 failed");
  EXPECT_FALSE(manager.capturing());
  EXPECT_FALSE(manager.acceptSample(sampleAt(15, 0.5, 1)));
  const json status = manager.status();
  EXPECT_EQ(status["sweep"]["state"], "paused");
  EXPECT_THAT(status["error"].get<std::string>(), HasSubstr("frame 12"));
  ok(manager, control::SweepStart{kAxial3030});
  EXPECT_TRUE(manager.capturing());
  EXPECT_EQ(manager.status()["sweep"]["samples"], 1);
}

TEST(SessionManager, AFullDiskPausesTheSweepAndKeepsWhatWasStored) {
  const auto root = test::freshTempDir();
  std::size_t stored = 0;
  {
    SessionManager manager(root, meanOfSlices);
    ok(manager, control::SessionNew{"felt", std::string("felt")});
    ok(manager, control::SweepStart{kAxial3030});
    // A file size limit makes the journal's appends fail as a full disk would (EFBIG).
    const std::uintmax_t journalBytes = std::filesystem::file_size(root / "felt" / "journal");
    {
      const test::FileSizeLimit limit(journalBytes + 1000);
      for (int k = 0; k < 200 && manager.acceptSample(sampleAt((k % 24) * 15.0, 0.5, k)); ++k)
        ++stored;
    }
    ASSERT_GT(stored, 0u);
    ASSERT_LT(stored, 200u);
    const json status = manager.status();
    EXPECT_EQ(status["sweep"]["state"], "paused");
    EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(), HasSubstr("storage error"));
    EXPECT_FALSE(manager.capturing());
  }
  SessionManager reopened(root, meanOfSlices);
  EXPECT_EQ(reopened.status()["session"]["samples"], stored);
}

TEST(SessionManager, ASessionAFullDiskKeptFromBeingMadeCanBeMadeOnceThereIsSpace) {
  // The half-made folder stayed: `session list` did not show it, yet `session new` of the same id
  // said it existed already.
  const auto root = test::freshTempDir();
  SessionManager manager(root, meanOfSlices);
  {
    const test::FileSizeLimit limit(10);  // session.json cannot be written
    const control::ProtocolError error = refused(manager, control::SessionNew{"felt", std::string("felt")});
    EXPECT_EQ(error.code, control::ErrorCode::StorageError);
    EXPECT_THAT(error.message, HasSubstr("session.json"));
  }
  EXPECT_FALSE(std::filesystem::exists(root / "felt"));
  EXPECT_EQ(ok(manager, control::SessionNew{"felt", std::string("felt")})["id"], "felt");
}

TEST(SessionManager, ReconstructsAndExportsTheFilesADesktopNeeds) {
  const auto root = test::freshTempDir();
  int previews = 0;
  SessionManager manager(root, meanOfSlices, [&](const Abrdf&, const std::filesystem::path& png) {
    std::ofstream(png) << "png";
    ++previews;
  });
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  EXPECT_EQ(refused(manager, control::Reconstruct{std::nullopt, "b"}).code, control::ErrorCode::Conflict);
  ok(manager, control::SweepStart{kAxial3030});
  for (int k = 0; k < 24; ++k)
    manager.acceptSample(sampleAt(k * 15.0, 0.25, k));
  ok(manager, control::SweepStop{});
  EXPECT_THAT(refused(manager, control::Reconstruct{std::nullopt, "needs-more"}).message,
              HasSubstr("missing slices"));
  const json reconstructed = ok(manager, control::Reconstruct{std::nullopt, "b"});
  const Abrdf table = io::readAbrdfExr(reconstructed["exr"].get<std::string>());
  EXPECT_FLOAT_EQ(table.at(3, 40).g(), 0.25);

  const json exported = ok(manager, control::Export{std::nullopt, "", std::string("b")});
  const std::filesystem::path directory = exported["directory"].get<std::string>();
  EXPECT_EQ(directory, root / "felt" / "export");
  EXPECT_EQ(exported["files"].size(), 4u);  // EXR, its preview, slices CSV, summary
  EXPECT_EQ(previews, 1);
  EXPECT_EQ(io::readSliceCsv(directory / "felt-slices.csv").sampleCount(), 24u);
  std::ifstream summaryFile(directory / "felt-summary.json");
  const json summary = json::parse(summaryFile);
  EXPECT_EQ(summary["material"], "felt");
  EXPECT_EQ(summary["samples"], 24);
}

// Sweeps all 24 bins of a slice with one value.
void sweepFully(SessionManager& manager, const SliceId& slice, double value) {
  ok(manager, control::SweepStart{slice});
  for (int k = 0; k < 24; ++k)
    ASSERT_TRUE(manager.acceptSample(sampleAt(k * 15.0, value, k)));
  ok(manager, control::SweepStop{});
}

TEST(SessionManager, AsksForTheDiagonalSweepsFirstAndSaysWhenTheAxialOnesAreNotNeeded) {
  IsotropyAssessment verdict{true, true, "the prior's anisotropy terms explain nothing more"};
  bool testFails = false;
  int testsRun = 0;
  std::size_t samplesSeen = 0;
  SessionManager manager(test::freshTempDir(), meanOfSlices, {}, [&](const SliceSet& slices) {
    ++testsRun;
    samplesSeen = slices.sampleCount();
    if (testFails) throw std::runtime_error("no prior file");
    return verdict;
  });
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  const std::vector<SliceId> diagonal{kDiagonal3030,
                                      {SliceKind::Diagonal, {75, 75}},
                                      {SliceKind::Diagonal, {30, 75}},
                                      {SliceKind::Diagonal, {75, 30}}};
  for (const SliceId& slice : diagonal) {
    EXPECT_EQ(manager.status()["next"], "slicecap sweep start diagonal " +
                                            std::to_string(slice.elevations.thetaIDeg) + " " +
                                            std::to_string(slice.elevations.thetaVDeg));
    EXPECT_FALSE(manager.status().contains("isotropy")) << "asked before the diagonal sweeps";
    if (slice != diagonal.back()) sweepFully(manager, slice, 0.5);
  }
  EXPECT_EQ(testsRun, 0);
  // The last diagonal sweep half done: the test runs, but "isotropic" needs 16 bins a slice.
  ok(manager, control::SweepStart{diagonal.back()});
  for (int k = 0; k < 12; ++k)
    ASSERT_TRUE(manager.acceptSample(sampleAt(k * 30.0, 0.5, k)));
  ok(manager, control::SweepStop{});
  json status = manager.status();
  EXPECT_EQ(testsRun, 1);
  EXPECT_EQ(samplesSeen, 84u);
  EXPECT_EQ(status["isotropy"]["axial_sweeps_needed"], true);
  EXPECT_EQ(status["isotropy"]["informative"], false);
  EXPECT_THAT(status["isotropy"]["reason"].get<std::string>(),
              HasSubstr("diagonal 75/30 has 12 of 24 (16 needed)"));
  EXPECT_EQ(status["isotropy"]["isotropic"], nullptr) << "unknown, not a finding";
  EXPECT_EQ(status["next"],
            "cannot tell yet whether the axial sweeps are needed (no anisotropy seen, but too few "
            "bins to rule it out: diagonal 75/30 has 12 of 24 (16 needed); sweep it again or "
            "measure the axial sweeps): slicecap sweep start axial 30 30 measures them; to pass "
            "again slowly: `slicecap sweep start diagonal 75 30` over 30 deg (empty), 60 deg "
            "(empty), 90 deg (empty), 120 deg (empty), 150 deg (empty), 180 deg (empty), 210 deg "
            "(empty), 240 deg (empty), 270 deg (empty), 300 deg (empty), 330 deg (empty)");
  // An anisotropic verdict stands on any coverage.
  verdict.isotropic = false;
  ok(manager, control::SweepStart{diagonal.back()});
  ASSERT_TRUE(manager.acceptSample(sampleAt(15.0, 0.5, 50)));
  ok(manager, control::SweepStop{});
  EXPECT_EQ(manager.status()["isotropy"]["isotropic"], false);
  EXPECT_EQ(manager.status()["isotropy"]["informative"], true);
  verdict.isotropic = true;
  sweepFully(manager, diagonal.back(), 0.5);

  status = manager.status();
  EXPECT_EQ(samplesSeen, 96u);  // one sample per filled bin
  EXPECT_EQ(status["isotropy"]["axial_sweeps_needed"], false);
  EXPECT_THAT(status["isotropy"]["reason"].get<std::string>(), HasSubstr("explain nothing"));
  EXPECT_EQ(status["next"],
            "the diagonal sweeps look isotropic, the axial sweeps are not needed: slicecap export "
            "felt -o DIR (to measure them anyway: slicecap sweep start axial 30 30)");
  manager.status();
  EXPECT_EQ(testsRun, 3) << "the same samples are not tested twice";

  // New samples are tested anew; while a sweep captures, the answer from before it stands.
  verdict = {false, true, "anisotropy terms cut the GCV score to 0.1"};
  ok(manager, control::SweepStart{kAxial3030});
  ASSERT_TRUE(manager.acceptSample(sampleAt(0, 0.5, 100)));
  EXPECT_EQ(manager.status()["isotropy"]["axial_sweeps_needed"], false);
  EXPECT_EQ(testsRun, 3);
  ok(manager, control::SweepStop{});
  status = manager.status();
  EXPECT_EQ(testsRun, 4);
  EXPECT_EQ(status["isotropy"]["isotropic"], false);
  EXPECT_EQ(status["next"],
            "the diagonal sweeps show anisotropy: slicecap sweep start axial 30 75");

  // A test that cannot run says why and asks for the axial sweeps.
  testFails = true;
  ok(manager, control::SweepRedo{kAxial3030});
  ok(manager, control::SweepStop{});
  status = manager.status();
  EXPECT_THAT(status["isotropy"]["error"].get<std::string>(), HasSubstr("no prior file"));
  EXPECT_EQ(status["next"], "slicecap sweep start axial 30 30");

  for (const SliceId& slice : sweepOrder())
    if (slice.kind == SliceKind::Axial) sweepFully(manager, slice, 0.5);
  EXPECT_EQ(manager.status()["next"], "every slice is swept: slicecap export felt -o DIR");
}

TEST(SessionManager, ExportsTablesMadeFromTheSamplesAsTheyAreNow) {
  const auto root = test::freshTempDir();
  SessionManager manager(root, meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  sweepFully(manager, kDiagonal3030, 0.25);
  ok(manager, control::Reconstruct{std::nullopt, "one-slice"});

  // Not all eight slices: the prior on the window cells, which reads any subset, is the default.
  json exported = ok(manager, control::Export{std::nullopt, "", std::nullopt});
  EXPECT_EQ(exported["method"], "prior-cells");
  EXPECT_FALSE(exported.contains("warnings"));
  const std::filesystem::path directory = exported["directory"].get<std::string>();
  EXPECT_FLOAT_EQ(io::readAbrdfExr(directory / "felt-abrdf-prior-cells.exr").at(3, 40).g(), 0.25);
  EXPECT_FLOAT_EQ(io::readAbrdfExr(directory / "felt-abrdf-one-slice.exr").at(3, 40).g(), 0.25);

  // A later sweep: the next export does not carry the tables made before it.
  sweepFully(manager, {SliceKind::Diagonal, {75, 75}}, 0.75);
  exported = ok(manager, control::Export{std::nullopt, "", std::nullopt});
  EXPECT_FLOAT_EQ(io::readAbrdfExr(directory / "felt-abrdf-prior-cells.exr").at(3, 40).g(), 0.5);
  ASSERT_EQ(exported["warnings"].size(), 1u);
  EXPECT_THAT(exported["warnings"][0].get<std::string>(),
              HasSubstr("abrdf-one-slice.exr (made from earlier samples) removed"));
  for (const json& file : exported["files"])
    EXPECT_THAT(file.get<std::string>(), Not(HasSubstr("one-slice")));
  EXPECT_FALSE(std::filesystem::exists(root / "felt" / "abrdf-one-slice.exr"));
  EXPECT_FALSE(std::filesystem::exists(directory / "felt-abrdf-one-slice.exr"));
  EXPECT_FALSE(ok(manager, control::Export{std::nullopt, "", std::nullopt}).contains("warnings"));

  // The asked method; one that fails refuses the export and says what would work.
  exported = ok(manager, control::Export{std::nullopt, "", std::string("a")});
  EXPECT_EQ(exported["method"], "a");
  EXPECT_FLOAT_EQ(io::readAbrdfExr(directory / "felt-abrdf-a.exr").at(3, 40).g(), 0.5);
  const control::ProtocolError failed =
      refused(manager, control::Export{std::nullopt, "", std::string("needs-more")});
  EXPECT_THAT(failed.message, HasSubstr("missing slices"));
  EXPECT_THAT(failed.message, HasSubstr("`--method prior` reconstructs from any subset"));

  // All eight slices: Method B, as the paper.
  for (const SliceId& slice : sweepOrder())
    if (slice.kind == SliceKind::Axial) sweepFully(manager, slice, 0.5);
  sweepFully(manager, {SliceKind::Diagonal, {30, 75}}, 0.5);
  sweepFully(manager, {SliceKind::Diagonal, {75, 30}}, 0.5);
  EXPECT_EQ(ok(manager, control::Export{std::nullopt, "", std::nullopt})["method"], "b");
}

TEST(SessionManager, AnExportFolderKeepsNoTableTheSamplesNoLongerGive) {
  const auto root = test::freshTempDir();
  const auto first = test::freshTempDir(), second = test::freshTempDir();
  SessionManager manager(root, meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  sweepFully(manager, kDiagonal3030, 0.25);
  ok(manager, control::Export{std::nullopt, first.string(), std::string("one-slice")});
  ASSERT_TRUE(std::filesystem::exists(first / "felt-abrdf-one-slice.exr"));
  // A second slice: one-slice can no longer be made; an export elsewhere removes the session's
  // table, and the next export into the first folder must not leave that folder's copy there.
  sweepFully(manager, {SliceKind::Diagonal, {75, 75}}, 0.75);
  EXPECT_TRUE(
      ok(manager, control::Export{std::nullopt, second.string(), std::nullopt}).contains("warnings"));
  ASSERT_FALSE(std::filesystem::exists(root / "felt" / "abrdf-one-slice.exr"));
  ok(manager, control::Export{std::nullopt, first.string(), std::nullopt});
  EXPECT_FALSE(std::filesystem::exists(first / "felt-abrdf-one-slice.exr"));
  EXPECT_TRUE(std::filesystem::exists(first / "felt-abrdf-prior-cells.exr"));
  EXPECT_TRUE(std::filesystem::exists(first / "felt-slices.csv"));
}

TEST(SessionManager, RefusesASecondManagerOnTheSameStorage) {
  const auto root = test::freshTempDir();
  {
    SessionManager manager(root, meanOfSlices);
    ok(manager, control::SessionNew{"felt", std::string("felt")});
    try {
      SessionManager second(root, meanOfSlices);
      ADD_FAILURE() << "two managers on one storage folder";
    } catch (const io::IoError& error) {
      EXPECT_THAT(error.what(), HasSubstr("in use by another slicecapd (pid "));
    }
  }
  SessionManager restarted(root, meanOfSlices);  // the lock went with the first
  EXPECT_EQ(restarted.status()["session"]["id"], "felt");
  EXPECT_TRUE(ok(restarted, control::SessionList{})["sessions"].size() == 1u) << "the lock is no session";
}

// A new rig's storage folder is made by its first daemon; a file where the folder should be is
// refused naming it, before any lock or session is touched.
TEST(SessionManager, MakesItsStorageFolderAndRefusesAFileInItsPlace) {
  const auto parent = test::freshTempDir();
  SessionManager made(parent / "new" / "storage", meanOfSlices);
  EXPECT_TRUE(std::filesystem::is_directory(parent / "new" / "storage"));
  std::ofstream(parent / "a-file") << "not a folder\n";
  try {
    SessionManager refused(parent / "a-file", meanOfSlices);
    ADD_FAILURE() << "a file taken for the storage folder";
  } catch (const io::IoError& error) {
    EXPECT_THAT(error.what(), HasSubstr((parent / "a-file").string() + ": cannot use as session storage"));
  }
}

TEST(SessionManager, RefusesTheSessionIdOfItsCurrentFile) {
  // A session named "current" became a folder where <storage>/current must be a file: its reply
  // was a storage error, and from then on no session could be made current (after a restart the
  // interrupted sweep was not found again).
  const auto root = test::freshTempDir();
  {
    SessionManager manager(root, meanOfSlices);
    const control::ProtocolError error = refused(manager, control::SessionNew{"felt", std::string("current")});
    EXPECT_EQ(error.code, control::ErrorCode::BadRequest);
    EXPECT_THAT(error.message, HasSubstr("session id 'current' is reserved"));
    ok(manager, control::SessionNew{"felt", std::string("felt")});
    EXPECT_EQ(refused(manager, control::SessionNew{"felt", std::string("current")}).code,
              control::ErrorCode::BadRequest);
    ok(manager, control::SweepStart{kAxial3030});
    ASSERT_TRUE(manager.acceptSample(sampleAt(0, 0.5, 0)));
  }
  SessionManager restarted(root, meanOfSlices);
  EXPECT_EQ(restarted.status()["session"]["id"], "felt");
  EXPECT_EQ(restarted.status()["sweep"]["samples"], 1);
}

TEST(SessionManager, ACurrentSessionThatCannotBeReadDoesNotKeepTheDaemonFromStarting) {
  // The constructor threw, so slicecapd exited at every start (systemd restarting it until it gave
  // up) and no session at all could be captured.
  const auto root = test::freshTempDir();
  {
    SessionManager manager(root, meanOfSlices);
    ok(manager, control::SessionNew{"felt", std::string("felt")});
    ok(manager, control::SweepStart{kAxial3030});
    ASSERT_TRUE(manager.acceptSample(sampleAt(0, 0.5, 0)));
  }
  std::ofstream(root / "felt" / "session.json") << "{\"format\": 1, \"id\": ";
  {
    SessionManager restarted(root, meanOfSlices);
    const json status = restarted.status();
    EXPECT_TRUE(status["session"].is_null());
    EXPECT_THAT(status["error"].get<std::string>(),
                HasSubstr("the current session 'felt' cannot be opened: "));
    EXPECT_THAT(status["error"].get<std::string>(), HasSubstr("felt/session.json"));
    EXPECT_EQ(refused(restarted, control::SessionResume{"felt"}).code, control::ErrorCode::StorageError);
    ok(restarted, control::SessionNew{"grey card", std::string("grey")});
    EXPECT_FALSE(restarted.status().contains("error"));
  }
  EXPECT_TRUE(std::filesystem::exists(root / "felt" / "journal")) << "nothing is removed";
}

TEST(SessionManager, NamesTheSparsestSliceOnceEverySliceIsSwept) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  for (const SliceId& slice : sweepOrder()) {
    const int bins = slice == kAxial3075 ? 5 : 20;
    ok(manager, control::SweepStart{slice});
    for (int k = 0; k < bins; ++k)
      ASSERT_TRUE(manager.acceptSample(sampleAt(k * 15.0, 0.5, k)));
    ok(manager, control::SweepStop{});
  }
  EXPECT_EQ(manager.status()["next"],
            "every slice is swept: slicecap export felt -o DIR (the sparsest, axial 30/75, has 5 "
            "of 24 bins: `slicecap sweep start axial 30 75` adds to it)");
}

TEST(SessionManager, AnErrorIsShownWithItsSweepOnly) {
  SessionManager manager(test::freshTempDir(), meanOfSlices);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  ok(manager, control::SweepStart{kAxial3030});
  manager.pauseSweep("the camera's recording has ended");
  EXPECT_EQ(manager.status()["error"], "the camera's recording has ended");
  ok(manager, control::SweepStop{});
  EXPECT_FALSE(manager.status().contains("error"));
}

}  // namespace
}  // namespace slicecap::daemon
