// The person-facing daemon commands against a live control socket served by a SessionManager in
// this process: what they print, their JSON, exit codes, and errors naming the socket.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/session_manager.hpp"

namespace slicecap::cli {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;

struct Result {
  int code;
  std::string out, err;
};

Abrdf flatTable(const SliceSet&, const std::string&) {
  Abrdf table;
  for (int light = 0; light < bonn::kDirectionCount; ++light)
    for (int view = 0; view < bonn::kDirectionCount; ++view)
      table.set(light, view, Rgb::gray(0.2));
  return table;
}

/// A control socket in a short /tmp path (Unix socket paths are limited to 108 bytes), served on
/// its own thread.
class LiveDaemon {
 public:
  explicit LiveDaemon(const std::filesystem::path& storage,
                      daemon::ReconstructFunction reconstruct = flatTable,
                      daemon::PreviewFunction preview = {})
      : manager_(storage, std::move(reconstruct), std::move(preview)) {
    socket_ = socketDir_ / "s.sock";
    const int listenFd = daemon::openListenSocket({socket_, 0600, std::nullopt});
    server_ =
        std::make_unique<daemon::ControlServer>(loop_, listenFd, [this](const control::Request& r) {
          json reply = daemon::replyOrThrow(manager_.handle(r.command));
          // As slicecapd's devices do when the camera cannot start: the sweep comes back paused.
          if (!failingDevice_.empty() && (std::holds_alternative<control::SweepStart>(r.command) ||
                                          std::holds_alternative<control::SweepRedo>(r.command))) {
            manager_.pauseSweep(failingDevice_);
            reply = manager_.status()["sweep"];
          }
          // What the daemon's frame loop adds to a status (record_frames), when a test sets it.
          if (std::holds_alternative<control::Status>(r.command) && !statusExtra_.is_null())
            reply.update(statusExtra_);
          return reply;
        });
    thread_ = std::thread([this] { loop_.run(); });
  }
  ~LiveDaemon() {
    loop_.stop();
    thread_.join();
    server_.reset();
  }

  Result run(std::vector<std::string> args) {
    args.push_back("--socket");
    args.push_back(socket_.string());
    std::ostringstream out, err;
    const int code = runCli(args, out, err);
    return {code, out.str(), err.str()};
  }

  daemon::SessionManager& manager() { return manager_; }
  /// Set before the first request only (the server thread reads it).
  void setStatusExtra(json extra) { statusExtra_ = std::move(extra); }
  /// Set before the first request only: every sweep start and redo fails with this reason.
  void setFailingDevice(std::string reason) { failingDevice_ = std::move(reason); }

 private:
  daemon::SessionManager manager_;
  json statusExtra_;
  std::string failingDevice_;
  daemon::EventLoop loop_;
  std::unique_ptr<daemon::ControlServer> server_;
  test::SocketDir socketDir_;  // the socket path must fit sun_path
  std::filesystem::path socket_;
  std::thread thread_;
};

TEST(DaemonCommands, StatusShowsTheRawFrameRecordingAndWhyItStopped) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  daemon.setStatusExtra({{"recording",
                          {{"directory", "/s/recordings/axial-30-30"},
                           {"frames_written", 40},
                           {"frames_queued", 0},
                           {"frames_dropped", 3},
                           {"error", "recording stopped: /s/x.png: No space left on device"}}}});
  const Result r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("raw frames recorded: 40 in /s/recordings/axial-30-30, 3 dropped"));
  EXPECT_THAT(r.out, HasSubstr("recording stopped: /s/x.png: No space left on device"));
}

TEST(DaemonCommands, StatusSaysWhichFinishedSweepsCellsAreNotReadAsTheyAre) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  const auto slice = [](const char* kind, int thetaDeg) {
    return json{{"name", std::string(kind) + " " + std::to_string(thetaDeg) + "/" +
                             std::to_string(thetaDeg)},
                {"kind", kind}, {"theta_i", thetaDeg}, {"theta_v", thetaDeg}};
  };
  daemon.setStatusExtra(
      {{"cell_texture",
        {{{"slice", slice("diagonal", 30)}, {"action", "as read"}, {"spread_percent", 2.0},
          {"reason", "spread 2 %, within the 10 % of a plain material"}},
         {{"slice", slice("diagonal", 75)}, {"action", "window centres"}, {"spread_percent", 64.0},
          {"reason", "texture (spread 64 % over 10 %) that the albedo factors do not explain"}}}}});
  const Result r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("cells, diagonal 75/75: window centres (texture (spread 64 % over "
                               "10 %) that the albedo factors do not explain)\n"));
  EXPECT_THAT(r.out, Not(HasSubstr("cells, diagonal 30/30")));  // a plain sweep says nothing
}

TEST(DaemonCommands, StatusNamesTheHdrBinsClippedAtEveryExposure) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  ASSERT_EQ(daemon.run({"session", "new", "steel", "--id", "steel"}).code, kExitOk);
  ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
  // Two exposures of bin 3 (45 deg), every window cell clipped in both; bin 5 has a cell clipped
  // in its long frame only.
  const auto hdrSample = [](int frame, double phiDeg, int level, bool clipped) {
    capture::FrameSample s{frame, std::uint64_t(frame), {30, phiDeg}, {30, phiDeg + 15}, Rgb::gray(0.2)};
    capture::HdrReading hdr;
    hdr.exposureLevel = level;
    for (int k = 0; k < capture::kHdrCellsPerSide * capture::kHdrCellsPerSide; ++k)
      hdr.cells.push_back({Rgb::gray(0.5), Rgb::gray(1e-6), clipped ? 1.0 : 0.5, clipped});
    hdr.irradiance = Rgb::gray(2.0);
    hdr.irradianceWeight = 1.0;
    s.hdr = std::move(hdr);
    return s;
  };
  daemon.manager().acceptSample(hdrSample(0, 45.0, 0, true));
  daemon.manager().acceptSample(hdrSample(1, 45.0, 1, true));
  daemon.manager().acceptSample(hdrSample(2, 75.0, 0, true));
  daemon.manager().acceptSample(hdrSample(3, 75.0, 1, false));
  Result r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("clipped at every exposure, a lower bound (sweep over them again slower): 45 deg\n"));
  // Bin 4 (60 deg) between the two is a gap the sweep left: a bin to pass again.
  EXPECT_THAT(r.out, HasSubstr("pass again slowly, axial 30/30: 60 deg (empty)\n"));
  EXPECT_THAT(r.out, HasSubstr("; pass again slowly over 60 deg (empty)\n"));
  r = daemon.run({"status", "--json"});
  EXPECT_EQ(json::parse(r.out)["sweep"]["clipped_bins"], json::array({3}));
}

TEST(DaemonCommands, ASessionFromNewToExport) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");

  Result r = daemon.run({"session", "new", "red felt", "--id", "felt"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("session felt (red felt)"));

  r = daemon.run({"sweep", "start", "axial", "30", "30"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("capturing"));
  for (int k = 0; k < 5; ++k)  // frames arrive through the frame loop in the daemon
    daemon.manager().acceptSample(
        {k, std::uint64_t(k), {30, k * 15.0}, {30, k * 15.0 + 15}, Rgb::gray(0.2)});

  r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("[#####...................] 5/24"));
  EXPECT_THAT(r.out, HasSubstr("next: keep sweeping axial 30/30"));

  r = daemon.run({"status", "--json"});
  const json status = json::parse(r.out);
  EXPECT_EQ(status["sweep"]["bins_filled"], 5);

  r = daemon.run({"status", "--watch", "--count", "2", "--interval", "0.05", "--json"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2);

  EXPECT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  r = daemon.run({"session", "list"});
  EXPECT_THAT(r.out, HasSubstr("* felt"));

  r = daemon.run({"export", "felt", "-o", (dir / "desk").string(), "--json"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  const json exported = json::parse(r.out);
  // One slice swept: the prior on the window cells, which reads any subset.
  EXPECT_EQ(exported["method"], "prior-cells");
  EXPECT_EQ(exported["files"].size(), 3u);  // EXR, slices CSV, summary (no preview injected)
  for (const json& file : exported["files"])
    EXPECT_TRUE(std::filesystem::exists(file.get<std::string>())) << file;

  r = daemon.run({"export", "felt", "-o", (dir / "desk").string(), "--method", "b"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("exported session felt (reconstructed with b)"));
  EXPECT_TRUE(std::filesystem::exists(dir / "desk" / "felt-abrdf-b.exr"));
  r = daemon.run({"export", "felt", "-o", (dir / "desk").string(), "--method", "nosuch"});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_THAT(r.err, HasSubstr("unknown method 'nosuch' (known: b, a,"));
}

// The texture folder is fetched as the daemon's reply lists it: a frame being written (.tmp) and
// a discarded sweep's folder stay behind on the box.
TEST(DaemonCommands, ExportCopiesTheTextureFilesTheReplyLists) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  ASSERT_EQ(daemon.run({"session", "new", "felt", "--id", "felt"}).code, kExitOk);
  ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
  for (int k = 0; k < 5; ++k)
    daemon.manager().acceptSample(
        {k, std::uint64_t(k), {30, k * 15.0}, {30, k * 15.0 + 15}, Rgb::gray(0.2)});
  ASSERT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  const std::filesystem::path texture = dir / "storage" / "felt" / "texture";
  for (const char* file : {"texture.json", "axial-30-30/0001.tex", "axial-30-30/0002.tex.tmp",
                           "axial-75-75.discarded/0001.tex"}) {
    std::filesystem::create_directories((texture / file).parent_path());
    std::ofstream(texture / file) << file;
  }
  const std::filesystem::path desk = dir / "desk";
  const Result r = daemon.run({"export", "felt", "-o", desk.string()});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  const std::filesystem::path copy = desk / "felt-texture";
  EXPECT_TRUE(std::filesystem::is_regular_file(copy / "texture.json"));
  EXPECT_TRUE(std::filesystem::is_regular_file(copy / "axial-30-30" / "0001.tex"));
  EXPECT_TRUE(std::filesystem::is_regular_file(copy / "slices.csv"));  // written by the export
  EXPECT_FALSE(std::filesystem::exists(copy / "axial-30-30" / "0002.tex.tmp"));
  EXPECT_FALSE(std::filesystem::exists(copy / "axial-75-75.discarded"));
}

TEST(DaemonCommands, AnExportFolderKeepsNoTableTheSamplesNoLongerGive) {
  // The daemon removed the table (with a warning) from the session and its own export folder, but
  // the copy an earlier `slicecap export` had put into DIR stayed there beside the new slices CSV.
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(
      dir / "storage",
      [](const SliceSet& slices, const std::string& method) {
        if (method == "halfway" && slices.slices().size() > 1)
          throw std::runtime_error("stands in for a method that cannot read these slices");
        return flatTable(slices, method);
      },
      [](const Abrdf&, const std::filesystem::path& png) { std::ofstream(png) << "its preview"; });
  const auto sweep = [&](const std::vector<std::string>& slice) {
    std::vector<std::string> start = {"sweep", "start"};
    start.insert(start.end(), slice.begin(), slice.end());
    ASSERT_EQ(daemon.run(start).code, kExitOk);
    for (int k = 0; k < 3; ++k)
      daemon.manager().acceptSample(
          {k, std::uint64_t(k), {30, k * 15.0}, {30, k * 15.0 + 15}, Rgb::gray(0.2)});
    ASSERT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  };
  ASSERT_EQ(daemon.run({"session", "new", "felt", "--id", "felt"}).code, kExitOk);
  sweep({"axial", "30", "30"});
  const auto desk = dir / "desk";
  ASSERT_EQ(daemon.run({"export", "felt", "-o", desk.string(), "--method", "halfway"}).code,
            kExitOk);
  ASSERT_TRUE(std::filesystem::exists(desk / "felt-abrdf-halfway.exr"));
  ASSERT_TRUE(std::filesystem::exists(desk / "felt-abrdf-halfway.png"));
  // Files the export did not write stay, whatever their names (it removes only what its own
  // earlier export listed in its manifest).
  std::ofstream(desk / "notes.txt") << "the operator's own file";
  std::ofstream(desk / "felt-abrdf-mine.exr") << "the operator's own table";
  sweep({"diagonal", "30", "30"});
  const Result r = daemon.run({"export", "felt", "-o", desk.string()});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.err, HasSubstr("abrdf-halfway.exr (made from earlier samples) removed"));
  EXPECT_FALSE(std::filesystem::exists(desk / "felt-abrdf-halfway.exr"));
  EXPECT_FALSE(std::filesystem::exists(desk / "felt-abrdf-halfway.png"));
  EXPECT_TRUE(std::filesystem::exists(desk / "felt-abrdf-prior-cells.exr"));
  EXPECT_TRUE(std::filesystem::exists(desk / "felt-slices.csv"));
  EXPECT_TRUE(std::filesystem::exists(desk / "notes.txt"));
  EXPECT_TRUE(std::filesystem::exists(desk / "felt-abrdf-mine.exr"));
}

TEST(DaemonCommands, ExportReplacesALinkPlantedInDirAndSaysWhatTheJournalSetAside) {
  const auto dir = test::freshTempDir();
  const auto desk = dir / "desk";
  std::filesystem::create_directories(desk);
  std::ofstream(dir / "victim") << "not slicecap's";
  std::filesystem::create_symlink(dir / "victim", desk / "felt-summary.json");
  {
    LiveDaemon daemon(dir / "storage");
    ASSERT_EQ(daemon.run({"session", "new", "felt", "--id", "felt"}).code, kExitOk);
    ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
    for (int k = 0; k < 3; ++k)
      daemon.manager().acceptSample(
          {k, std::uint64_t(k), {30, k * 15.0}, {30, k * 15.0 + 15}, Rgb::gray(0.2)});
    ASSERT_EQ(daemon.run({"sweep", "redo", "axial", "30", "30"}).code, kExitOk);
    ASSERT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  }
  // One flipped byte in the redo record: its 3 samples must stay discarded, and every text
  // command says so, naming the journal and the line.
  const auto journal = dir / "storage" / "felt" / "journal";
  std::string bytes;
  {
    std::ifstream in(journal, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::size_t redo = bytes.find("\"redo\"");
  ASSERT_NE(redo, std::string::npos);
  const std::size_t line =
      std::size_t(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(redo), '\n')) + 1;
  bytes[redo + 2] = 'x';
  std::ofstream(journal, std::ios::binary | std::ios::trunc) << bytes;
  const std::string said = journal.string() + " line " + std::to_string(line);

  LiveDaemon daemon(dir / "storage");
  const Result status = daemon.run({"status"});
  EXPECT_THAT(status.out, HasSubstr("3 set aside")) << status.out;
  EXPECT_THAT(status.out, HasSubstr(said)) << status.out;
  EXPECT_THAT(daemon.run({"session", "show", "felt"}).out, HasSubstr(said));
  // With nothing counted left, the export is refused; its refusal is not about the journal.
  ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
  daemon.manager().acceptSample({9, 9, {30, 0.0}, {30, 15.0}, Rgb::gray(0.2)});
  ASSERT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  const Result exported = daemon.run({"export", "felt", "-o", desk.string()});
  ASSERT_EQ(exported.code, kExitOk) << exported.err;
  EXPECT_THAT(exported.err, HasSubstr("warning: " + said)) << exported.err;
  std::ifstream victim(dir / "victim");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(victim), {}), "not slicecap's");
  EXPECT_FALSE(std::filesystem::is_symlink(desk / "felt-summary.json"));
  // A session whose description is damaged is listed as damaged, not left out.
  const auto description = dir / "storage" / "felt" / "session.json";
  std::ofstream(description) << "{";
  EXPECT_THAT(daemon.run({"session", "list"}).out,
              HasSubstr("felt  damaged: " + description.string()));
}

// A sweep refused for its decoding (what the daemon's decoding watch asks for as a run ends):
// its samples are set aside, the status says why under the slice and as the error, and the export
// says so, with nothing counted left, in its refusal; a later sample of the slice counts again.
TEST(DaemonCommands, ARefusedSweepIsSaidByTheStatusAndTheExport) {
  const auto dir = test::freshTempDir();
  const auto desk = dir / "desk";
  std::filesystem::create_directories(desk);
  LiveDaemon daemon(dir / "storage");
  ASSERT_EQ(daemon.run({"session", "new", "felt", "--id", "felt"}).code, kExitOk);
  ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
  const std::uint64_t run = daemon.manager().nextRecordNumber().value();
  for (int k = 0; k < 3; ++k)
    daemon.manager().acceptSample(
        {k, std::uint64_t(k), {30, k * 15.0}, {30, k * 15.0 + 15}, Rgb::gray(0.2)});
  ASSERT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  const SliceId slice{SliceKind::Axial, {30, 30}};
  EXPECT_TRUE(daemon.manager().refuseSweep(slice, "decoding broken: the window's G ...", run));
  const Result status = daemon.run({"status"});
  EXPECT_THAT(status.out, HasSubstr("0 samples, 3 set aside (sweep refused)")) << status.out;
  EXPECT_THAT(status.out, HasSubstr("    refused: decoding broken: the window's G ...")) << status.out;
  EXPECT_THAT(status.out, HasSubstr("sweep axial 30/30 refused, the run's 3 samples set aside"))
      << status.out;
  const Result exported = daemon.run({"export", "felt", "-o", desk.string()});
  EXPECT_NE(exported.code, kExitOk);
  EXPECT_THAT(exported.err, HasSubstr("no samples to reconstruct from; sweep axial 30/30 refused: "
                                      "the run's 3 samples are set aside"))
      << exported.err;
  ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
  daemon.manager().acceptSample({9, 9, {30, 0.0}, {30, 15.0}, Rgb::gray(0.2)});
  ASSERT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
  const Result again = daemon.run({"export", "felt", "-o", desk.string()});
  ASSERT_EQ(again.code, kExitOk) << again.err;
  EXPECT_THAT(again.err,
              HasSubstr("warning: sweep axial 30/30 refused: the run's 3 samples are set aside"))
      << again.err;
}

// A run that ended in a pause (here the LED's error) and was then refused: the status's error
// says both, the pause's reason first. A redo then discards the slice's samples and forgets the
// refusal's reason, and the samples set aside are still said to be a refused sweep's, not the
// journal's damage.
TEST(DaemonCommands, ARefusalKeepsThePausesReasonAndARedoKeepsWhyItsSamplesWereSetAside) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  ASSERT_EQ(daemon.run({"session", "new", "felt", "--id", "felt"}).code, kExitOk);
  ASSERT_EQ(daemon.run({"sweep", "start", "axial", "30", "30"}).code, kExitOk);
  const std::uint64_t run = daemon.manager().nextRecordNumber().value();
  for (int k = 0; k < 2; ++k)
    daemon.manager().acceptSample(
        {k, std::uint64_t(k), {30, k * 15.0}, {30, k * 15.0 + 15}, Rgb::gray(0.2)});
  daemon.manager().pauseSweep("LED error: the GPIO line is busy");
  ASSERT_TRUE(daemon.manager().refuseSweep({SliceKind::Axial, {30, 30}}, "decoding broken", run));
  const Result paused = daemon.run({"status"});
  EXPECT_THAT(paused.out, HasSubstr("LED error: the GPIO line is busy")) << paused.out;
  EXPECT_THAT(paused.out, HasSubstr("sweep axial 30/30 refused, the run's 2 samples set aside"))
      << paused.out;
  ASSERT_EQ(daemon.run({"sweep", "redo", "axial", "30", "30"}).code, kExitOk);
  const Result redone = daemon.run({"status"});
  EXPECT_THAT(redone.out, HasSubstr("2 set aside (sweep refused)")) << redone.out;
  EXPECT_THAT(redone.out, Not(HasSubstr("damaged journal"))) << redone.out;
}

TEST(DaemonCommands, RefusesAWatchCountThatIsNoWholeNumberAndSaysWhyARequestIsTooLong) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  for (const char* count : {"0", "-1", "1.5", "9223372036854775808", "1e300"}) {
    const Result r = daemon.run({"status", "--watch", "--count", count, "--interval", "0.05"});
    EXPECT_EQ(r.code, kExitUsage) << count;
    EXPECT_THAT(r.err, HasSubstr("--count must be a whole number")) << count;
  }
  // The daemon answers a request it cannot read without its id; its reason reaches the person.
  const Result r = daemon.run({"session", "new", std::string(70000, 'x'), "--id", "big"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_THAT(r.err, HasSubstr("request longer than 65536 bytes"));
}

// The devices' fields a person acts on, each a line of its own (they were only in --json).
TEST(DaemonCommands, StatusShowsTheHdrDecodingCameraFramesRoomLightAndDecodingCheck) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  daemon.setStatusExtra({{"hdr", "HDR, 2 exposures by LED pairs (8000 us, 500 us)"},
                         {"decoding", {{"decoding", "measured-curve"}, {"note", "rms 0.004"}}},
                         {"camera_frames",
                          {{"delivered", 240},
                           {"dropped", 3},
                           {"led_pattern", "2 on, 2 off"},
                           {"led_clean_fraction", 0.5},
                           {"timing", "sensor timestamps"}}},
                         {"room_light", {{"to_led", 0.1}, {"change", 0.4}, {"change_to_led", 0.04}}},
                         {"decoding_check",
                          {{"black_reading", 1.012},
                           {"black_reading_step", 0.031},
                           {"black_reading_step_sigmas", 6.5},
                           {"window_at_black_channel", "G"},
                           {"window_at_black", 0.97}}},
                         {"tuning_file",
                          {{"setting", "auto"},
                           {"file", "/usr/share/slicecap/tuning/slicecap-imx708-pisp.json"},
                           {"reason", "the processed path on a Pi 5"}}}});
  const Result r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("hdr: HDR, 2 exposures by LED pairs (8000 us, 500 us)\n"));
  EXPECT_THAT(r.out, HasSubstr("decoding: measured-curve (rms 0.004)\n"));
  EXPECT_THAT(r.out, HasSubstr("camera: 240 frames, 3 dropped, LED 2 on, 2 off, 50.0 % with one "
                               "LED state over the rows read (sensor timestamps)\n"));
  EXPECT_THAT(r.out, HasSubstr("room light: 10.0 % of the LED's light, changing by 4.0 % of it "
                               "between LED-off frames\n"));
  EXPECT_THAT(r.out, HasSubstr("decoding check: black patch reads 1.012 of its albedo, stepping "
                               "3.1 % from a frame to the next (6.5 standard errors), window G "
                               "97.0 % at code 0\n"));
  EXPECT_THAT(r.out, HasSubstr("tuning file: /usr/share/slicecap/tuning/slicecap-imx708-pisp.json "
                               "(tuning_file = auto: the processed path on a Pi 5)\n"));
}

TEST(DaemonCommands, StatusSaysWhetherTheAxialSweepsAreNeeded) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  daemon.setStatusExtra({{"isotropy",
                          {{"isotropic", true},
                           {"informative", true},
                           {"axial_sweeps_needed", false},
                           {"reason", "anisotropy terms explain nothing more"}}}});
  const Result r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("isotropy: isotropic, the axial sweeps are not needed (anisotropy "
                               "terms explain nothing more)"));
}

TEST(DaemonCommands, StatusShowsTheDaemonsWarningsAndTheExposure) {
  const auto dir = test::freshTempDir();
  LiveDaemon daemon(dir / "storage");
  daemon.setStatusExtra({{"warnings", {"camera = v4l2 with gain empty"}},
                         {"exposure", "camera video0: exposure locked at 8000 us, gain 4"}});
  const Result r = daemon.run({"status"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_THAT(r.out, HasSubstr("warning: camera = v4l2 with gain empty\n"));
  EXPECT_THAT(r.out, HasSubstr("exposure: camera video0: exposure locked at 8000 us, gain 4\n"));
}

TEST(DaemonCommands, RefusalsAndBadUsageHaveTheirExitCodes) {
  LiveDaemon daemon(test::freshTempDir());
  Result r = daemon.run({"sweep", "start", "axial", "30", "30"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_THAT(r.err, HasSubstr("no current session"));
  EXPECT_EQ(daemon.run({"sweep", "start", "axial", "30", "45"}).code, kExitUsage);
  EXPECT_EQ(daemon.run({"sweep", "sideways", "axial", "30", "30"}).code, kExitUsage);
  EXPECT_EQ(daemon.run({"session", "show"}).code, kExitUsage);
  r = daemon.run({"session", "show", "nobody"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_THAT(r.err, HasSubstr("no session 'nobody'"));
}

TEST(DaemonCommands, ASweepTheCameraLeavesPausedIsAFailure) {
  // `sweep start` printed "paused" with the camera's error and exited 0: a script went on as if
  // the sweep were capturing.
  LiveDaemon daemon(test::freshTempDir());
  daemon.setFailingDevice("camera error: /dev/video0: No such device");
  ASSERT_EQ(daemon.run({"session", "new", "felt", "--id", "felt"}).code, kExitOk);
  Result r = daemon.run({"sweep", "start", "axial", "30", "30"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_THAT(r.err, HasSubstr("sweep axial 30/30 is paused, not capturing: camera error: "
                               "/dev/video0: No such device"));
  EXPECT_THAT(r.err, HasSubstr("`slicecap sweep start axial 30 30` continues"));
  r = daemon.run({"sweep", "start", "axial", "30", "30", "--json"});  // continuing it fails alike
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_EQ(json::parse(r.out).at("code"), "unavailable");
  EXPECT_EQ(daemon.run({"sweep", "redo", "axial", "30", "30"}).code, kExitFailure);
  EXPECT_EQ(daemon.run({"sweep", "stop"}).code, kExitOk);
}

TEST(DaemonCommands, WithJsonAnErrorIsAlsoAJsonObjectOnStdout) {
  // A script parsing stdout got nothing: the error went only to stderr.
  LiveDaemon daemon(test::freshTempDir());
  Result r = daemon.run({"sweep", "start", "axial", "30", "30", "--json"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_THAT(r.err, HasSubstr("no current session"));
  json error = json::parse(r.out);
  EXPECT_THAT(error.at("error").get<std::string>(), HasSubstr("no current session"));
  EXPECT_EQ(error.at("code"), "conflict") << "the daemon's error code";
  r = daemon.run({"session", "show", "nobody", "--json"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_THAT(json::parse(r.out).at("error").get<std::string>(), HasSubstr("no session 'nobody'"));
  r = daemon.run({"sweep", "start", "axial", "30", "45", "--json"});  // bad usage keeps its code
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_THAT(r.err, HasSubstr("THETA_V '45'"));
  EXPECT_THAT(json::parse(r.out).at("error").get<std::string>(), HasSubstr("THETA_V '45'"));
  // No daemon: the error names the socket on both streams.
  std::ostringstream out, err;
  const std::vector<std::string> args = {"status", "--json", "--socket",
                                         "/tmp/slicecap-no-daemon.sock"};
  EXPECT_EQ(runCli(args, out, err), kExitFailure);
  EXPECT_THAT(err.str(), HasSubstr("/tmp/slicecap-no-daemon.sock"));
  error = json::parse(out.str());
  EXPECT_THAT(error.at("error").get<std::string>(), HasSubstr("/tmp/slicecap-no-daemon.sock"));
  EXPECT_FALSE(error.contains("code")) << "not a refusal by the daemon";
  // Without --json, stdout stays empty as before.
  r = daemon.run({"sweep", "start", "axial", "30", "30"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(DaemonCommands, AMissingDaemonIsNamedWithItsSocket) {
  std::ostringstream out, err;
  const std::vector<std::string> args = {"status", "--socket", "/tmp/slicecap-no-daemon.sock"};
  EXPECT_EQ(runCli(args, out, err), kExitFailure);
  EXPECT_THAT(err.str(), HasSubstr("/tmp/slicecap-no-daemon.sock"));
}

}  // namespace
}  // namespace slicecap::cli
