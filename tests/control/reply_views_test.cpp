// The typed replies: each view's JSON reads back as the same view, replies as the daemon wrote
// them before the views read and write back byte for byte, and a missing field is named.
#include "slicecap/control/reply_views.hpp"

#include <gtest/gtest.h>

namespace slicecap::control {
namespace {

using nlohmann::json;

SessionView fullSession() {
  SessionView session;
  session.id = "s1";
  session.material = "brushed steel";
  session.createdUtc = "2026-12-02T10:00:00Z";
  session.directory = "/var/lib/slicecap/s1";
  session.samples = 7;
  session.slices = {{{SliceKind::Diagonal, {30, 30}}, 5, 4, 0, std::nullopt, false, std::nullopt},
                    {{SliceKind::Axial, {75, 30}}, 2, 1, 3, 2, true, "decoding broken: ..."}};
  session.tornTailBytesDropped = 12;
  session.corruptJournalLines = {4, 9};
  session.journalDamage = {{9, "journal line 9: unreadable", {"axial 75/30"}, 3, 1}};
  session.current = true;
  return session;
}

SweepView pausedSweep() {
  SweepView sweep;
  sweep.slice = {SliceKind::Axial, {30, 75}};
  sweep.state = "paused";
  sweep.bins = std::vector<bool>(kBinsPerSlice, false);
  sweep.bins[3] = true;
  sweep.binsFilled = 1;
  sweep.clippedBins = {3};
  sweep.samples = 9;
  sweep.acceptedThisRun = 2;
  sweep.rejected = {{"too_few_markers", 4}, {"elevation_off", 1}};
  sweep.viewElevationErrorDeg = -1.25;
  sweep.pauseReason = "camera error: gone";
  return sweep;
}

TEST(ReplyViews, SessionRoundTrips) {
  const json written = toJson(fullSession());
  EXPECT_EQ(toJson(sessionFromJson(written)), written);
  EXPECT_EQ(written["slices"][1]["name"], "axial 75/30");
  EXPECT_EQ(written["slices"][1]["samples_set_aside"], 3);
  EXPECT_EQ(written["slices"][1]["samples_refused"], 2);
  EXPECT_FALSE(written["slices"][0].contains("samples_set_aside"));
  EXPECT_FALSE(written["slices"][0].contains("samples_refused"));
  EXPECT_FALSE(written["slices"][0].contains("damaged"));
  EXPECT_FALSE(written["slices"][0].contains("refused"));
  EXPECT_EQ(written["slices"][1]["refused"], "decoding broken: ...");
  const SessionView read = sessionFromJson(written);
  EXPECT_EQ(read.slices.at(1).refused, "decoding broken: ...");
  EXPECT_EQ(read.slices.at(1).slice, (SliceId{SliceKind::Axial, {75, 30}}));
  EXPECT_EQ(read.journalDamage.at(0).samplesLost, 1u);
  EXPECT_EQ(read.current, true);
}

TEST(ReplyViews, SweepRoundTripsWithAndWithoutAPosedFrame) {
  SweepView sweep = pausedSweep();
  const json written = toJson(sweep);
  EXPECT_EQ(toJson(sweepFromJson(written)), written);
  EXPECT_EQ(sweepFromJson(written).rejected.at("too_few_markers"), 4u);
  EXPECT_EQ(sweepFromJson(written).clippedBins, std::vector<int>{3});
  // No clipped bin (every sweep of one exposure, a daemon from before the field): no key.
  json none = written;
  none.erase("clipped_bins");
  EXPECT_TRUE(sweepFromJson(none).clippedBins.empty());
  EXPECT_EQ(toJson(sweepFromJson(none)), none);
  sweep.viewElevationErrorDeg.reset();
  sweep.pauseReason.reset();
  sweep.state = "capturing";
  const json capturing = toJson(sweep);
  // Always present, null before a posed frame: a client reads the key without checking for it.
  ASSERT_TRUE(capturing.contains("view_elevation_error_deg"));
  EXPECT_TRUE(capturing["view_elevation_error_deg"].is_null());
  EXPECT_FALSE(capturing.contains("pause_reason"));
  EXPECT_EQ(toJson(sweepFromJson(capturing)), capturing);
}

TEST(ReplyViews, StatusRoundTrips) {
  StatusView status;
  status.next = "slicecap sweep stop";
  EXPECT_EQ(toJson(statusFromJson(toJson(status))), toJson(status));
  EXPECT_TRUE(toJson(status)["session"].is_null());
  status.session = fullSession();
  status.session->current.reset();
  status.sweep = pausedSweep();
  status.isotropy = IsotropyView{std::nullopt, std::nullopt, false, true, "too few bins"};
  status.error = "camera error: gone";
  status.recording = RecordingView{"/s1/frames", 10, 1, 2, "recording stopped: disk full"};
  status.exposure = "locked at 4000 us";
  status.warnings = {"one", "two"};
  const json written = toJson(status);
  EXPECT_TRUE(written["isotropy"]["isotropic"].is_null());
  EXPECT_EQ(toJson(statusFromJson(written)), written);
  EXPECT_FALSE(written.contains("pass_again"));  // none to pass again: the key is left out
}

TEST(ReplyViews, TheBinsToPassAgainRoundTrip) {
  StatusView status;
  status.next = "keep sweeping";
  const SliceId diagonal{SliceKind::Diagonal, {75, 75}}, axial{SliceKind::Axial, {30, 30}};
  status.passAgain = {{axial, 210.0, "empty"}, {diagonal, 90.0, "peak_not_reached"}};
  const json written = toJson(status);
  ASSERT_EQ(written["pass_again"].size(), 2u);
  EXPECT_EQ(written["pass_again"][1]["slice"]["name"], toString(diagonal));
  EXPECT_EQ(written["pass_again"][1]["azimuth_deg"], 90.0);
  EXPECT_EQ(written["pass_again"][1]["reason"], "peak_not_reached");
  const StatusView read = statusFromJson(written);
  ASSERT_EQ(read.passAgain.size(), 2u);
  EXPECT_EQ(read.passAgain[0].slice, axial);
  EXPECT_EQ(read.passAgain[0].azimuthDeg, 210.0);
  EXPECT_EQ(read.passAgain[0].reason, "empty");
  EXPECT_EQ(read.passAgain[1].slice, diagonal);
  EXPECT_EQ(toJson(read), written);
  json unreadable = written;
  unreadable["pass_again"][0].erase("reason");
  EXPECT_THROW(statusFromJson(unreadable), ReplyError);
}

TEST(ReplyViews, TheFinishedSweepsTextureVerdictsRoundTrip) {
  StatusView status;
  status.next = "keep sweeping";
  const SliceId diagonal{SliceKind::Diagonal, {75, 75}}, axial{SliceKind::Axial, {30, 30}};
  status.cellTextures = {
      {axial, "as read", std::nullopt, "texture not measured: 3 frames ..., 8 needed"},
      {diagonal, "window centres", 64.0, "texture (spread 64 % over 10 %) ..."}};
  const json written = toJson(status);
  ASSERT_EQ(written["cell_texture"].size(), 2u);
  EXPECT_EQ(written["cell_texture"][0]["spread_percent"], nullptr);
  EXPECT_EQ(written["cell_texture"][1]["slice"]["name"], toString(diagonal));
  EXPECT_EQ(written["cell_texture"][1]["action"], "window centres");
  EXPECT_EQ(written["cell_texture"][1]["spread_percent"], 64.0);
  const StatusView read = statusFromJson(written);
  ASSERT_EQ(read.cellTextures.size(), 2u);
  EXPECT_EQ(read.cellTextures[0].slice, axial);
  EXPECT_EQ(read.cellTextures[0].spreadPercent, std::nullopt);
  EXPECT_EQ(read.cellTextures[1].spreadPercent, 64.0);
  EXPECT_EQ(read.cellTextures[1].reason, status.cellTextures[1].reason);
  EXPECT_EQ(toJson(read), written);
  EXPECT_FALSE(toJson(StatusView{}).contains("cell_texture"));  // none: the key is left out
  json unreadable = written;
  unreadable["cell_texture"][1].erase("action");
  EXPECT_THROW(statusFromJson(unreadable), ReplyError);
}

TEST(ReplyViews, IsotropyErrorKeepsOnlyTheErrorAndTheAdvice) {
  const IsotropyView failed{"isotropy test: no prior", std::nullopt, true, true, ""};
  const json written = toJson(failed);
  EXPECT_EQ(written, (json{{"error", "isotropy test: no prior"}, {"axial_sweeps_needed", true}}));
  EXPECT_EQ(toJson(isotropyFromJson(written)), written);
}

TEST(ReplyViews, ExportRoundTripsAndListsTheTextureFiles) {
  ExportView reply{"s1", "/s1/export", {"/s1/export/s1-abrdf-b.exr"}, "b", "fitted: ward",
                   {"a warning"}, "/s1/texture", {"slices.csv", "diagonal-30-30/frame-1.exr"},
                   std::nullopt};
  const json written = toJson(reply);
  EXPECT_EQ(written["texture_files"].size(), 2u);
  EXPECT_EQ(toJson(exportFromJson(written)), written);
  reply.texture.reset();
  reply.textureFiles.clear();
  reply.textureSkipped = "sweep axial 30/30 is capturing";
  const json skipped = toJson(reply);
  EXPECT_FALSE(skipped.contains("texture_files"));
  EXPECT_EQ(toJson(exportFromJson(skipped)), skipped);
}

// A status line as slicecapd wrote it before the views: read and written again, byte for byte.
TEST(ReplyViews, ADaemonStatusLineIsWrittenBackByteForByte) {
  const std::string line =
      R"({"error":"camera error: gone","isotropy":{"axial_sweeps_needed":true,"informative":true,)"
      R"("isotropic":false,"reason":"anisotropic"},"next":"keep sweeping","session":{"id":"s1",)"
      R"("material":"felt","samples":3,"slices":[{"bins_filled":2,"kind":"diagonal","name":)"
      R"("diagonal 30/30","samples":3,"theta_i":30,"theta_v":30}]},"sweep":{"accepted_this_run":3,)"
      R"("bins":[true,false,true],"bins_filled":2,"rejected":{"elevation_off":2},"samples":3,)"
      R"("slice":{"kind":"diagonal","name":"diagonal 30/30","theta_i":30,"theta_v":30},"state":)"
      R"("capturing","view_elevation_error_deg":0.5}})";
  EXPECT_EQ(toJson(statusFromJson(json::parse(line))).dump(), line);
}

// The devices' part of a status as slicecapd wrote it before StatusView held it (raw keys patched
// in by the frame loop): read and written again byte for byte, so a client of either reads both.
TEST(ReplyViews, TheDevicesStatusLineOfThePreviousDaemonIsWrittenBackByteForByte) {
  const std::string line =
      R"({"camera_frames":{"delivered":40,"dropped":1,"led_clean_fraction":0.75,"led_pattern":)"
      R"("2 on, 2 off","timing":"sensor timestamps"},"decoding":{"decoding":"measured-curve",)"
      R"("note":"fit rms 0.01"},"exposure":"camera x: metered 4000 us","hdr":"HDR, 2 exposures",)"
      R"("next":"keep sweeping","recording":{"directory":"/s1/recordings/axial-30-30",)"
      R"("frames_dropped":0,"frames_queued":1,"frames_written":20},"room_light":{"change":0.04,)"
      R"("change_to_led":0.004,"to_led":0.1},"session":null,"sweep":null,"texture":)"
      R"({"bins_filled":3,"damaged_frames_removed":0,"directory":"/s1/texture","frames_stored":5,)"
      R"("resolution":64,"session_frames_stored":9,"stored_mb":1.5},"warnings":["room light"]})";
  const StatusView read = statusFromJson(json::parse(line));
  EXPECT_EQ(toJson(read).dump(), line);
  ASSERT_TRUE(read.cameraFrames && read.decoding && read.roomLight && read.texture);
  EXPECT_EQ(read.cameraFrames->dropped, 1u);
  EXPECT_EQ(read.decoding->decoding, "measured-curve");
  EXPECT_EQ(read.roomLight->changeToLed, 0.004);
  EXPECT_EQ(read.texture->sessionFramesStored, 9u);
  EXPECT_EQ(read.hdr, "HDR, 2 exposures");
}

// A room light without any figure yet is left out, as the daemon always did.
TEST(ReplyViews, ARoomLightWithoutFiguresIsLeftOut) {
  StatusView status;
  status.roomLight = RoomLightView{};
  EXPECT_FALSE(toJson(status).contains("room_light"));
  status.roomLight->toLed = 0.2;
  EXPECT_EQ(toJson(status)["room_light"], (json{{"to_led", 0.2}}));
}

// The decoding check and the tuning file are read back as written; a check without figures is
// left out, and a camera's own tuning is a null file.
TEST(ReplyViews, TheDecodingCheckAndTheTuningFileAreReadBackAsWritten) {
  StatusView status;
  status.decodingCheck = DecodingCheckView{};
  status.tuningFile = TuningFileView{"off", std::nullopt, "tuning_file = off"};
  json written = toJson(status);
  EXPECT_FALSE(written.contains("decoding_check"));
  EXPECT_TRUE(written["tuning_file"]["file"].is_null());
  status.decodingCheck = DecodingCheckView{
      0.98, 0.031, 6.5, "G", 0.97, "G", 0.75, 0.25, -40.0, -55.0, "refused as the run ends", "R",
      -0.013, 9.0};
  status.tuningFile->file = "/usr/share/slicecap/tuning/slicecap-imx708-pisp.json";
  written = toJson(status);
  EXPECT_EQ(written["decoding_check"]["window_at_black_channel"], "G");
  const StatusView read = statusFromJson(written);
  ASSERT_TRUE(read.decodingCheck && read.tuningFile);
  EXPECT_EQ(read.decodingCheck->blackReadingStep, 0.031);
  EXPECT_EQ(read.decodingCheck->blackReadingStepSigmas, 6.5);
  EXPECT_EQ(read.decodingCheck->windowAtBlack, 0.97);
  EXPECT_EQ(read.decodingCheck->windowUnlitChannel, "G");
  EXPECT_EQ(read.decodingCheck->windowUnlit, 0.75);
  EXPECT_EQ(read.decodingCheck->windowUnlitSigmas, -40.0);
  EXPECT_EQ(read.decodingCheck->windowUnlitVerdict, "refused as the run ends");
  EXPECT_EQ(read.tuningFile->file, status.tuningFile->file);
  EXPECT_EQ(toJson(read), written);
}

// The stop's reply: the stopped sweep with its recording and texture beside its own keys.
TEST(ReplyViews, SweepStopCarriesTheRecordingAndTheTexture) {
  SweepStopView stop{pausedSweep(), RecordingView{"/s1/r", 3, 0, 0, std::nullopt}, std::nullopt};
  const json written = toJson(stop);
  EXPECT_EQ(written["recording"]["frames_written"], 3);
  EXPECT_FALSE(written.contains("texture"));
  json sweepOnly = written;
  sweepOnly.erase("recording");
  EXPECT_EQ(sweepOnly, toJson(pausedSweep()));
}

TEST(ReplyViews, AMissingFieldIsNamed) {
  json sweep = toJson(pausedSweep());
  sweep.erase("bins_filled");
  try {
    sweepFromJson(sweep);
    FAIL() << "a sweep without bins_filled was read";
  } catch (const ReplyError& error) {
    EXPECT_NE(std::string(error.what()).find("bins_filled"), std::string::npos) << error.what();
  }
  json session = toJson(fullSession());
  session["samples"] = "many";
  EXPECT_THROW(sessionFromJson(session), ReplyError);
}

}  // namespace
}  // namespace slicecap::control
