// The daemon's frame loop on the file camera with a stand-in pipeline: frames become samples in
// the session, the LED follows the sweep and is off whenever nothing captures, and camera
// failures and the end of a recording pause the sweep without losing samples; texture capture
// (through a fake sink) sees every frame, and its failures pause the sweep.
#include "slicecap/daemon/daemon.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <fstream>
#include <functional>
#include <thread>

#include "../support/request_as_user.hpp"
#include "../support/test_support.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/control_client.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/hal/camera_error.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/hal/file_led.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::daemon {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};
constexpr int kFrames = 20;  // alternating LED on/off: 10 samples

std::filesystem::path writeRecording(const std::filesystem::path& directory) {
  io::Recording header;
  header.createdBy = "daemon_test";
  header.camera = vision::defaultSimulatedCamera();
  header.camera.intrinsics = {32, 24, 30.0, 30.0, 15.5, 11.5};
  header.encoding = PixelEncoding::Srgb8;
  header.slice = io::RecordedSlice{kAxial3030};
  header.target = vision::defaultTarget();
  io::RecordingWriter writer(directory, header);
  Image image{32, 24, 3, 8, std::vector<std::uint16_t>(32 * 24 * 3, 128)};
  for (int k = 0; k < kFrames; ++k)
    writer.append(image, {"", 1000 + k * 33'000, k % 2 == 0, 10'000.0, 1.0});
  return directory;
}

// Stands in for the capture pipeline: a sample per LED-on frame, spread over the bins.
capture::FrameProcessor standInPipeline() {
  return [](const hal::Frame& frame, const SliceId&) {
    capture::FrameOutcome outcome;
    outcome.viewElevationErrorDeg = 1.5;
    if (!frame.metadata.ledOn) {
      outcome.kind = capture::FrameOutcome::Kind::Ambient;
      return outcome;
    }
    const double phi = double(frame.metadata.sequence / 2 % 24) * 15.0;
    outcome.kind = capture::FrameOutcome::Kind::Sample;
    outcome.sample = capture::FrameSample{frame.metadata.timestampUs,
                                          frame.metadata.sequence,
                                          {30, phi},
                                          {30, phi + 15},
                                          Rgb::gray(0.3)};
    return outcome;
  };
}

// What a fake texture sink saw, shared with the test.
struct TextureLog {
  int framesSeen = 0;
  int samplesStored = 0;
  int opened = 0;
  std::optional<int> failAtSample;  // add() throws io::IoError from this sample on (disk full)
  std::optional<std::string> failToOpen;
  int runsKept = 0;
  // What settleTexture was given, each time a session was made current.
  std::vector<std::vector<capture::SweepRefusal>> settled;
};

class FakeTextureSink : public TextureSink {
 public:
  explicit FakeTextureSink(std::shared_ptr<TextureLog> log) : log_(std::move(log)) {}
  void add(const hal::Frame&, const capture::FrameOutcome& outcome,
           const std::vector<capture::AmbientTerm>&) override {
    ++log_->framesSeen;
    if (outcome.kind != capture::FrameOutcome::Kind::Sample) return;
    if (log_->failAtSample && log_->samplesStored + 1 >= *log_->failAtSample)
      throw io::IoError("texture/axial-30-30/b00.tex: No space left on device");
    ++log_->samplesStored;
  }
  control::TextureProgressView status() const override {
    control::TextureProgressView view;
    view.directory = "texture";
    view.resolution = 8;
    view.framesStored = std::size_t(log_->samplesStored);
    return view;
  }
  void beginRun() override { runStart_ = log_->samplesStored; }
  capture::RunTextureFrames run() const override {
    return {std::uint64_t(runStart_), std::uint64_t(log_->samplesStored)};
  }
  void keepRun() override { ++log_->runsKept; }
  std::size_t setAsideRun() override {
    const std::size_t frames = std::size_t(log_->samplesStored - runStart_);
    log_->samplesStored = runStart_;
    return frames;
  }

 private:
  std::shared_ptr<TextureLog> log_;
  int runStart_ = 0;
};

// The sweep's texture through the fake sink; no recordings.
class FakeOutputs : public SessionOutputs {
 public:
  explicit FakeOutputs(std::shared_ptr<TextureLog> log) : log_(std::move(log)) {}
  std::optional<io::Recording> recordingHeader(const SliceId&) override { return std::nullopt; }
  bool capturesTexture() const override { return true; }
  std::unique_ptr<TextureSink> openTexture(const SliceId&, const std::filesystem::path&,
                                           const std::vector<capture::SweepRefusal>&) override {
    ++log_->opened;
    if (log_->failToOpen) throw io::IoError(*log_->failToOpen);
    return std::make_unique<FakeTextureSink>(log_);
  }
  std::size_t settleTexture(const std::filesystem::path&,
                            const std::vector<capture::SweepRefusal>& refused) override {
    log_->settled.push_back(refused);
    std::size_t frames = 0;
    for (const capture::SweepRefusal& r : refused)
      if (r.textureFrames) frames += r.textureFrames->to - r.textureFrames->from;
    return frames;
  }

 private:
  std::shared_ptr<TextureLog> log_;
};

// No export in these tests: the reconstruction is never asked for.
class NoTables : public SessionTables {
 public:
  Abrdf reconstruct(const SliceSet&, const std::string&) override { return Abrdf(); }
};

// A live camera (it has a ready descriptor, so the daemon strobes the LED and meters the
// exposure) over a grey scene whose brightest pixels sit at `sceneLevel` of full scale at 10 ms:
// linear in exposure, clipped at full scale, a lock taking effect two frames late, an exposure
// range of 100 us..`maxExposureUs`; `frames` frames, then the end of the stream.
struct LiveCameraLog {
  std::vector<hal::ExposureSetting> locks;
  double sceneLevel = 0.15;  // at 10 ms
  double maxExposureUs = 100'000.0;
  bool canLock = true;
  std::optional<int> failAtLock;    // this lock (1-based) throws, as a device that went away
  std::optional<int> refuseAtLock;  // this lock (1-based) is refused, the camera left as it was
  int lockDelayFrames = 2;          // frames taken before a lock reaches the sensor
  int frames = 40;                  // per start
  bool streaming = false;
  bool eightBit = false;  // 8-bit processed frames (a UVC camera) instead of linear 16-bit ones
};

class FakeLiveCamera : public hal::Camera {
 public:
  explicit FakeLiveCamera(std::shared_ptr<LiveCameraLog> log)
      : log_(std::move(log)), ready_(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC)) {}
  ~FakeLiveCamera() override { ::close(ready_); }
  std::string id() const override { return "fake-live"; }
  // As V4L2 and libcamera: one device, which cannot be configured while it streams.
  hal::ConfigResult configure(hal::CameraConfig& config) override {
    if (log_->streaming) throw std::logic_error("fake-live: configure while streaming");
    if (config.exposureUs) exposureUs_ = *config.exposureUs;  // a configured exposure is applied
    return {};
  }
  void start() override {
    log_->streaming = true;
    nextDueUs_ = clock_.nowUs() + kPeriodUs;
    armReady();
    framesSinceStart_ = 0;
    appliedLocks_ = 0;
    pending_.clear();
  }
  void stop() override { log_->streaming = false; }
  std::optional<int> readyDescriptor() const override { return ready_; }
  hal::ExposureLock lockExposure(const hal::ExposureSetting& wanted) override {
    if (!log_->canLock) return {std::nullopt, "no manual exposure"};
    ++lockCalls_;
    if (log_->failAtLock && lockCalls_ == *log_->failAtLock)
      throw hal::CameraError("fake-live: cannot set the exposure: No such device");
    if (log_->refuseAtLock && lockCalls_ == *log_->refuseAtLock)
      return {std::nullopt, "fake-live refused a manual gain"};
    const hal::ExposureSetting set{std::clamp(wanted.exposureUs, 100.0, log_->maxExposureUs),
                                   wanted.gain.value_or(1.0)};
    log_->locks.push_back(set);
    pending_.push_back({sequence_ + std::uint64_t(log_->lockDelayFrames), set.exposureUs});
    return {set, ""};
  }
  hal::CaptureResult nextFrame(std::chrono::milliseconds) override {
    // As a camera: a frame every period on the steady clock, its descriptor readable once it is
    // there, stamped as libcamera stamps it (its rows read out from the timestamp on, exposed for
    // the exposure before), so the daemon's strobe can tell which LED state each frame saw.
    if (clock_.nowUs() < nextDueUs_) {
      armReady();
      return {hal::CaptureResult::Status::Timeout, {}, ""};
    }
    if (framesSinceStart_++ >= log_->frames)
      return {hal::CaptureResult::Status::EndOfStream, {}, ""};
    while (!pending_.empty() && pending_.front().first <= sequence_) {
      exposureUs_ = pending_.front().second;
      ++appliedLocks_;
      pending_.erase(pending_.begin());
    }
    const double level = std::min(1.0, log_->sceneLevel * exposureUs_ / 10'000.0);
    hal::Frame frame;
    frame.encoding = PixelEncoding::Linear16;
    frame.image = {32, 24, 3, 16,
                   std::vector<std::uint16_t>(32 * 24 * 3, std::uint16_t(level * 65535.0))};
    if (log_->eightBit) {
      frame.encoding = PixelEncoding::Srgb8;
      frame.image = {32, 24, 3, 8,
                     std::vector<std::uint16_t>(
                         32 * 24 * 3, std::uint16_t(std::lround(ToneCurve::srgb().encode(level) * 255)))};
    }
    const std::int64_t timestampUs = nextDueUs_;
    nextDueUs_ += kPeriodUs;
    armReady();
    frame.metadata = {sequence_, timestampUs, exposureUs_, 1.0, true, appliedLocks_};
    frame.metadata.exposureStartUs = timestampUs - std::int64_t(exposureUs_);
    frame.metadata.lineTimeUs = kLineTimeUs;  // its 24 rows read out in 9.6 ms
    ++sequence_;
    return {hal::CaptureResult::Status::Frame, std::move(frame), ""};
  }

 private:
  void armReady() {
    itimerspec spec{};
    spec.it_value.tv_sec = nextDueUs_ / 1'000'000;
    spec.it_value.tv_nsec = (nextDueUs_ % 1'000'000) * 1000;
    ::timerfd_settime(ready_, TFD_TIMER_ABSTIME, &spec, nullptr);
  }

  static constexpr std::int64_t kPeriodUs = 33'333;
  static constexpr double kLineTimeUs = 400.0;
  std::shared_ptr<LiveCameraLog> log_;
  int ready_;
  hal::SteadyClock clock_;
  std::int64_t nextDueUs_ = 0;
  std::uint64_t sequence_ = 0;
  int framesSinceStart_ = 0;
  int lockCalls_ = 0;
  std::uint32_t appliedLocks_ = 0;
  double exposureUs_ = 30'000.0;  // the camera's own auto exposure before any lock
  std::vector<std::pair<std::uint64_t, double>> pending_;
};

class DaemonOnFileCamera : public ::testing::Test {
 protected:
  // The camera and stand-in pipeline the tests run with, as slicecapd's rig gives them.
  class TestRig : public CaptureRig {
   public:
    TestRig(DaemonOnFileCamera& test, std::filesystem::path recording,
            std::optional<std::uint64_t> failAtSequence)
        : test_(test), recording_(std::move(recording)), failAtSequence_(failAtSequence) {}
    std::shared_ptr<hal::Camera> camera(const SliceId&) override {
      // One camera serves every slice, as in slicecapd.
      if (test_.liveCamera_) {
        if (!test_.liveCameraDevice_)
          test_.liveCameraDevice_ = std::make_shared<FakeLiveCamera>(test_.liveCamera_);
        return test_.liveCameraDevice_;
      }
      hal::FileCameraOptions options;
      options.failAtSequence = failAtSequence_;
      return std::make_shared<hal::FileCamera>(recording_, test_.clock_, options);
    }
    capture::LiveFrameProcessor pipeline(const SliceId&, capture::FrameObserver observer,
                                         const std::optional<ToneCurve>&) override {
      return capture::settledAtOnce(
          [inner = standInPipeline(), observer](const hal::Frame& frame, const SliceId& slice) {
            capture::FrameOutcome outcome = inner(frame, slice);
            if (observer) observer(frame, outcome, {});
            return outcome;
          });
    }
    // With bracketing_ as slicecapd's rig gives it: a 32 x 24 camera over the default target
    // (which the grey frames do not show); else none.
    std::optional<BracketSubject> bracketSubject(const SliceId&) override {
      if (!test_.bracketing_) return std::nullopt;
      vision::CameraModel camera = vision::defaultSimulatedCamera();
      camera.intrinsics = {32, 24, 30.0, 30.0, 15.5, 11.5};
      return BracketSubject{vision::defaultTarget(), camera};
    }

   private:
    DaemonOnFileCamera& test_;
    std::filesystem::path recording_;
    std::optional<std::uint64_t> failAtSequence_;
  };

  void start(std::optional<std::uint64_t> failAtSequence = std::nullopt,
             std::shared_ptr<TextureLog> texture = nullptr) {
    dir_ = test::freshTempDir();
    if (prepareStorage_) prepareStorage_(dir_ / "storage");
    const auto recording = writeRecording(dir_ / "recording");
    socket_ = socketDir_ / "s.sock";
    ledLog_ = dir_ / "led.log";
    DaemonParts parts;
    parts.storage = dir_ / "storage";
    parts.rig = std::make_unique<TestRig>(*this, recording, failAtSequence);
    parts.cameraConfig = {32, 24, PixelEncoding::Srgb8, configuredExposureUs_, std::nullopt, 4};
    parts.led = std::make_unique<hal::FileLed>(ledLog_, clock_);
    if (texture) parts.outputs = std::make_unique<FakeOutputs>(texture);
    parts.tables = std::make_unique<NoTables>();
    parts.clientLimits.socketGroup = socketGroup_;
    listening_.emplace(ListenSpec{socket_, 0600, std::nullopt, {}});
    daemon_ = std::make_unique<Daemon>(std::move(parts), listening_->fd());
    stopped_ = false;
    thread_ = std::thread([this] {
      daemon_->run();
      stopped_ = true;
    });
  }

  // Whether run() returned by itself within `seconds` (else it is stopped here).
  bool stoppedWithin(int seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (!stopped_ && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const bool byItself = stopped_;
    if (!byItself) daemon_->stop();
    thread_.join();
    daemon_.reset();
    listening_.reset();
    return byItself;
  }

  // Until the LED has been switched on (a sweep captures).
  bool ledWentOn() {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const auto leds = ledLog();
      if (std::any_of(leds.begin(), leds.end(), [](const auto& e) { return e.on; })) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  void TearDown() override {
    if (daemon_) {
      daemon_->stop();
      thread_.join();
      daemon_.reset();
    }
  }

  json call(const control::Command& command) { return control::ControlClient(socket_).call(command); }

  json waitForPause() {
    for (int attempt = 0; attempt < 500; ++attempt) {
      json status = call(control::Status{});
      if (!status["sweep"].is_null() && status["sweep"]["state"] == "paused") return status;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "the sweep never paused";
    return call(control::Status{});
  }

  // A new session and a sweep of kAxial3030 until it pauses (the camera's frames run out).
  json sweepUntilPaused() {
    call(control::SessionNew{"grey card", std::string("grey")});
    call(control::SweepStart{kAxial3030});
    return waitForPause();
  }

  std::vector<hal::LedEvent> ledLog() const { return hal::readLedLog(ledLog_); }

  hal::SteadyClock clock_;
  std::optional<double> configuredExposureUs_;
  std::shared_ptr<LiveCameraLog> liveCamera_;  // set: a live camera instead of the recording
  bool bracketing_ = false;  // the rig has a bracket subject
  // Writes what the storage holds before the daemon starts (a session a crash left).
  std::function<void(const std::filesystem::path&)> prepareStorage_;
  std::shared_ptr<hal::Camera> liveCameraDevice_;
  test::SocketDir socketDir_;  // the socket path must fit sun_path
  std::filesystem::path dir_, socket_, ledLog_;
  std::optional<std::uint32_t> socketGroup_;  // who may connect besides root and this uid
  std::optional<ListenSocket> listening_;
  std::unique_ptr<Daemon> daemon_;
  std::thread thread_;
  std::atomic<bool> stopped_ = false;
};

TEST_F(DaemonOnFileCamera, FramesBecomeSamplesAndTheLedGoesOffWhenTheRecordingEnds) {
  start();
  EXPECT_FALSE(ledLog().back().on);
  const json status = sweepUntilPaused();
  EXPECT_EQ(status["sweep"]["samples"], kFrames / 2);
  EXPECT_EQ(status["sweep"]["bins_filled"], kFrames / 2);
  EXPECT_DOUBLE_EQ(status["sweep"]["view_elevation_error_deg"].get<double>(), 1.5);
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(), HasSubstr("recording has ended"));
  const std::vector<hal::LedEvent> log = ledLog();
  EXPECT_FALSE(log.back().on);
  EXPECT_GE(std::count_if(log.begin(), log.end(), [](const hal::LedEvent& e) { return e.on; }),
            kFrames / 2);  // strobed with the frames
  call(control::SweepStop{});
  EXPECT_EQ(call(control::Status{})["session"]["samples"], kFrames / 2);
}

TEST_F(DaemonOnFileCamera, WhatTheCameraCouldNotDoAsConfiguredIsLogged) {
  // A recording's exposure is what it was: the file camera adjusts a locked exposure away, as a
  // V4L2 camera without manual exposure does.
  configuredExposureUs_ = 1234.0;
  testing::internal::CaptureStderr();
  start();
  const json status = sweepUntilPaused();
  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_THAT(log, HasSubstr("adjusted the configuration: "));
  EXPECT_THAT(log, HasSubstr("exposure"));
  // The operator over SSH sees it in the status too.
  ASSERT_TRUE(status.contains("warnings")) << status.dump();
  EXPECT_THAT(status["warnings"].back().get<std::string>(),
              HasSubstr("adjusted the configuration: "));
}

TEST_F(DaemonOnFileCamera, ACameraFailurePausesTheSweepAndKeepsEverySampleBeforeIt) {
  start(std::uint64_t{7});
  const json status = sweepUntilPaused();
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(), HasSubstr("camera error"));
  EXPECT_THAT(status["error"].get<std::string>(), HasSubstr("injected camera failure"));
  EXPECT_EQ(status["sweep"]["samples"], 4);  // frames 0, 2, 4, 6 had the LED on
  EXPECT_FALSE(ledLog().back().on);
  // The daemon is still there: the status answers, and the sweep can go on.
  call(control::SweepStart{kAxial3030});
  EXPECT_GE(waitForPause()["sweep"]["samples"].get<int>(), 4);
}

TEST_F(DaemonOnFileCamera, TheTextureSeesEveryFrameOfTheSweepAndItsStatusIsShown) {
  auto texture = std::make_shared<TextureLog>();
  start(std::nullopt, texture);
  const json status = sweepUntilPaused();
  EXPECT_EQ(texture->framesSeen, kFrames);
  EXPECT_EQ(texture->samplesStored, kFrames / 2);
  EXPECT_EQ(texture->runsKept, 1) << "the run ended in a pause, unrefused: kept";
  EXPECT_EQ(status["texture"]["frames_stored"], kFrames / 2);
  EXPECT_EQ(call(control::SweepStop{})["texture"]["frames_stored"], kFrames / 2);
  EXPECT_EQ(texture->opened, 1);
  // A redone sweep starts its texture afresh, as its samples: the slice's folder goes (whatever
  // the sink kept there), the other slices' stay, and a new sink indexes what is left.
  const auto folder = dir_ / "storage" / "grey" / kTextureFolder;
  std::filesystem::create_directories(folder / "axial-30-30");
  std::filesystem::create_directories(folder / "axial-30-75");
  std::ofstream(folder / "axial-30-30" / "b00-00000001.tex") << "old sweep";
  texture->samplesStored = 0;
  call(control::SweepRedo{kAxial3030});
  EXPECT_FALSE(std::filesystem::exists(folder / "axial-30-30"));
  EXPECT_TRUE(std::filesystem::exists(folder / "axial-30-75"));
  waitForPause();
  EXPECT_EQ(texture->opened, 2);
  EXPECT_EQ(texture->samplesStored, kFrames / 2);
}

// A paused sweep has no camera and no run: stopping the daemon then judges nothing (keeping the
// texture's last run would delete what a refused run, whose set-aside failed, replaced).
TEST_F(DaemonOnFileCamera, StoppingWithTheSweepPausedKeepsNoTextureRun) {
  auto texture = std::make_shared<TextureLog>();
  start(std::nullopt, texture);
  sweepUntilPaused();
  ASSERT_EQ(texture->runsKept, 1) << "the run ended in a pause, unrefused: kept";
  stoppedWithin(0);
  EXPECT_EQ(texture->runsKept, 1) << "no run was live as the daemon stopped";
}

// A crash between a refusal's journal record and the move of the run's texture frames: the record
// names the frames, and the daemon has the texture set them aside when it makes the session
// current (at its start, and again on each resume: idempotent), before any sweep opens it.
TEST_F(DaemonOnFileCamera, MakingASessionCurrentSetsAsideTheTextureFramesOfItsRefusedRuns) {
  auto texture = std::make_shared<TextureLog>();
  prepareStorage_ = [](const std::filesystem::path& storage) {
    capture::SessionStore store = capture::SessionStore::create(storage, "grey", "grey card");
    const std::uint64_t run = store.nextRecordNumber();
    store.recordSample(kAxial3030, {1, 1, {30, 0.0}, {30, 15.0}, Rgb::gray(0.2)});
    store.refuse(kAxial3030, "decoding broken", run, capture::RunTextureFrames{3, 7});
    std::ofstream(storage / "current") << "grey\n";
  };
  start(std::nullopt, texture);
  const json status = call(control::Status{});
  ASSERT_EQ(texture->settled.size(), 1u);
  ASSERT_EQ(texture->settled[0].size(), 1u);
  EXPECT_EQ(texture->settled[0][0].slice, kAxial3030);
  ASSERT_TRUE(texture->settled[0][0].textureFrames);
  EXPECT_EQ(texture->settled[0][0].textureFrames->from, 3u);
  EXPECT_EQ(texture->settled[0][0].textureFrames->to, 7u);
  EXPECT_EQ(texture->opened, 0) << "settled before any sweep opens the texture";
  EXPECT_THAT(status["error"].get<std::string>(),
              HasSubstr("4 frames of refused sweep runs, left in the texture, set aside now"));
  call(control::SessionNew{"other", std::string("other")});
  ASSERT_EQ(texture->settled.size(), 2u);
  EXPECT_TRUE(texture->settled[1].empty());
  call(control::SessionResume{"grey"});
  ASSERT_EQ(texture->settled.size(), 3u);
  EXPECT_EQ(texture->settled[2].size(), 1u);
}

TEST_F(DaemonOnFileCamera, ATextureStorageErrorPausesTheSweepAndKeepsTheSamples) {
  auto texture = std::make_shared<TextureLog>();
  texture->failAtSample = 3;
  start(std::nullopt, texture);
  const json status = sweepUntilPaused();
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(),
              HasSubstr("texture storage error"));
  EXPECT_THAT(status["error"].get<std::string>(), HasSubstr("No space left on device"));
  EXPECT_EQ(texture->samplesStored, 2);
  EXPECT_EQ(status["sweep"]["samples"], 3);  // the window sample of the failed frame is kept
  EXPECT_FALSE(ledLog().back().on);
}

TEST_F(DaemonOnFileCamera, ATextureThatCannotBeOpenedPausesTheSweepWithTheReason) {
  auto texture = std::make_shared<TextureLog>();
  texture->failToOpen = "texture/texture.json: this session's texture has 64 texels across";
  start(std::nullopt, texture);
  call(control::SessionNew{"grey card", std::string("grey")});
  const json reply = call(control::SweepStart{kAxial3030});
  EXPECT_EQ(reply["state"], "paused");
  EXPECT_THAT(reply["pause_reason"].get<std::string>(), HasSubstr("64 texels across"));
  const json status = waitForPause();
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(), HasSubstr("64 texels across"));
  EXPECT_EQ(status["sweep"]["samples"], 0);
  EXPECT_FALSE(ledLog().back().on);
}

TEST_F(DaemonOnFileCamera, ALiveCameraIsMeteredWithTheLedOnThenLockedForTheSweep) {
  liveCamera_ = std::make_shared<LiveCameraLog>();  // 0.15 at 10 ms: 23 ms reaches 0.35
  testing::internal::CaptureStderr();
  start();
  const json status = sweepUntilPaused();
  const std::string log = testing::internal::GetCapturedStderr();
  const std::vector<hal::ExposureSetting>& locks = liveCamera_->locks;
  ASSERT_GE(locks.size(), 2u);
  EXPECT_DOUBLE_EQ(locks.front().exposureUs, ExposureMeterParams{}.startExposureUs);
  const double finalLevel = liveCamera_->sceneLevel * locks.back().exposureUs / 10'000.0;
  EXPECT_NEAR(finalLevel, 0.35, 0.35 * 0.25) << locks.back().exposureUs;
  ASSERT_TRUE(status.contains("exposure")) << status.dump();
  EXPECT_THAT(status["exposure"].get<std::string>(), HasSubstr("exposure locked at"));
  EXPECT_THAT(log, HasSubstr("exposure locked at"));
  EXPECT_FALSE(status.contains("warnings")) << status.dump();
  // The metering's frames are never samples: fewer than half of all frames became samples.
  const int samples = status["sweep"]["samples"].get<int>();
  EXPECT_GT(samples, 0);
  EXPECT_LT(samples, liveCamera_->frames / 2);
  // The LED stayed on through the metering and was strobed after it: it went off once per
  // sample frame after the metering (and at the end), not also during the metering.
  const std::vector<hal::LedEvent> leds = ledLog();
  EXPECT_FALSE(leds.back().on);
  const auto offs = std::count_if(leds.begin(), leds.end(), [](const auto& e) { return !e.on; });
  EXPECT_LE(offs, samples + 2);
}

TEST_F(DaemonOnFileCamera, ALinearLiveCameraTakesNoBracketAndTheSessionSaysItsDecoding) {
  liveCamera_ = std::make_shared<LiveCameraLog>();
  bracketing_ = true;
  start();
  const json status = sweepUntilPaused();
  ASSERT_TRUE(status.contains("decoding")) << status.dump();
  EXPECT_EQ(status["decoding"]["decoding"], "linear");
  EXPECT_FALSE(status.contains("warnings")) << status.dump();
  // Only the metering locked: its last lock is the sweep's (no bracket of x1/32 .. x4 after it).
  const auto& locks = liveCamera_->locks;
  ASSERT_GE(locks.size(), 2u);
  EXPECT_GT(locks.back().exposureUs, 15'000.0);
  const json recorded = json::parse(std::ifstream(
      dir_ / "storage" / status["session"]["id"].get<std::string>() / "decoding" / "axial-30-30.json"));
  EXPECT_EQ(recorded["decoding"], "linear");
  EXPECT_EQ(recorded["camera"], "fake-live");
}

TEST_F(DaemonOnFileCamera, ABracketWithoutTheTargetFallsBackToSrgbAndEveryStatusSaysSo) {
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->eightBit = true;
  liveCamera_->frames = 120;  // the metering, 9 bracket locks two frames late each, then samples
  bracketing_ = true;
  testing::internal::CaptureStderr();
  start();
  const json status = sweepUntilPaused();
  const std::string log = testing::internal::GetCapturedStderr();
  ASSERT_TRUE(status.contains("decoding")) << status.dump();
  EXPECT_EQ(status["decoding"]["decoding"], "srgb");
  ASSERT_TRUE(status.contains("warnings")) << status.dump();
  const std::string warning = status["warnings"].dump();
  EXPECT_THAT(warning, HasSubstr("fake-live"));
  EXPECT_THAT(warning, HasSubstr("the target was not found"));
  EXPECT_THAT(warning, HasSubstr("decodes its 8-bit frames as sRGB"));
  EXPECT_THAT(log, HasSubstr("decoding srgb"));
  // The bracket ran after the metering (its x1/32 step) and the sweep went on at the metered
  // exposure, with samples.
  const auto& locks = liveCamera_->locks;
  ASSERT_GE(locks.size(), 10u);
  EXPECT_DOUBLE_EQ(locks.back().exposureUs, locks[locks.size() - 10].exposureUs);
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0);
}

TEST_F(DaemonOnFileCamera, AMeteringAtTheCamerasExposureLimitSaysItIsOffTheTarget) {
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->sceneLevel = 0.01;  // 350 ms needed
  liveCamera_->maxExposureUs = 30'000.0;
  start();
  const json status = sweepUntilPaused();
  ASSERT_FALSE(liveCamera_->locks.empty());
  EXPECT_DOUBLE_EQ(liveCamera_->locks.back().exposureUs, 30'000.0);
  EXPECT_THAT(status["exposure"].get<std::string>(), HasSubstr("off the target"));
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0);
}

TEST_F(DaemonOnFileCamera, ALiveCameraThatCannotLockItsExposureIsAWarning) {
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->canLock = false;
  start();
  const json status = sweepUntilPaused();
  ASSERT_TRUE(status.contains("warnings")) << status.dump();
  EXPECT_THAT(status["warnings"].back().get<std::string>(),
              HasSubstr("exposure not locked (no manual exposure)"));
  EXPECT_FALSE(status.contains("exposure")) << "the same text once, as the warning";
  // Nothing was metered: every frame reached the strobe. Its 30 ms auto exposure leaves no gap
  // between frames for a switch, so each block's first frame is mixed and rejected: fewer than
  // half the frames are LED-on samples (2 on, 2 off, one of each pair lost); a switch made late
  // on a loaded machine lengthens a block, so the bound leaves room for it.
  EXPECT_EQ(status["camera_frames"]["delivered"], liveCamera_->frames) << status.dump();
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0) << status.dump();
  EXPECT_LE(status["sweep"]["samples"].get<int>(), liveCamera_->frames * 3 / 4) << status.dump();
}

TEST_F(DaemonOnFileCamera, ACameraFailingDuringTheMeteringPausesTheSweep) {
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->failAtLock = 2;  // the first metering step
  start();
  const json status = sweepUntilPaused();
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(),
              HasSubstr("exposure metering: fake-live: cannot set the exposure"));
  EXPECT_EQ(status["sweep"]["samples"], 0);
  EXPECT_FALSE(ledLog().back().on);
  // It said "metering the exposure with the LED on" after the sweep had paused.
  EXPECT_FALSE(status.contains("exposure")) << status.dump();
}

TEST_F(DaemonOnFileCamera, AFailureAtTheFirstLockStopsTheCameraAndTheSweepCanContinue) {
  // The camera was left streaming: every later sweep start failed with "configure while
  // streaming" until the daemon restarted, and the pause was called a camera error.
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->failAtLock = 1;
  start();
  json status = sweepUntilPaused();
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(),
              HasSubstr("exposure metering: fake-live: cannot set the exposure"));
  EXPECT_FALSE(liveCamera_->streaming);
  EXPECT_FALSE(status.contains("exposure")) << status.dump();
  EXPECT_FALSE(ledLog().back().on);
  call(control::SweepStart{kAxial3030});  // continues the paused sweep: metered, then samples
  status = waitForPause();
  EXPECT_THAT(status["sweep"]["pause_reason"].get<std::string>(), HasSubstr("stream has ended"));
  EXPECT_THAT(status["exposure"].get<std::string>(), HasSubstr("exposure locked at"));
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0);
}

TEST_F(DaemonOnFileCamera, TheMeteringMeasuresOnlyFramesExposedWithItsSetting) {
  // libcamera on a Pi: a lock reaches the sensor behind the requests already queued, about 7
  // frames later. Metering the 5th frame after each change locked 2 stops off the target and
  // called it on target.
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->lockDelayFrames = 8;
  liveCamera_->frames = 60;
  start();
  const json status = sweepUntilPaused();
  const std::vector<hal::ExposureSetting>& locks = liveCamera_->locks;
  ASSERT_GE(locks.size(), 2u);
  const double finalLevel = liveCamera_->sceneLevel * locks.back().exposureUs / 10'000.0;
  EXPECT_NEAR(finalLevel, 0.35, 0.35 * 0.25) << locks.back().exposureUs;
  EXPECT_THAT(status["exposure"].get<std::string>(), Not(HasSubstr("off the target")));
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0);
}

TEST_F(DaemonOnFileCamera, ARefusedMeteringStepKeepsTheLastLockAndSaysSo) {
  // The lock before the refused one stays: the sweep runs at it, and its auto exposure does not.
  liveCamera_ = std::make_shared<LiveCameraLog>();
  liveCamera_->refuseAtLock = 2;
  start();
  const json status = sweepUntilPaused();
  ASSERT_EQ(liveCamera_->locks.size(), 1u);
  EXPECT_THAT(status["exposure"].get<std::string>(), HasSubstr("exposure locked at 10000 us"));
  EXPECT_THAT(status["exposure"].get<std::string>(),
              HasSubstr("the camera refused the next step (fake-live refused a manual gain)"));
  EXPECT_FALSE(status.contains("warnings")) << status.dump();
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0);
}

TEST_F(DaemonOnFileCamera, AConfiguredExposureIsNotMetered) {
  liveCamera_ = std::make_shared<LiveCameraLog>();
  configuredExposureUs_ = 8000.0;
  start();
  const json status = sweepUntilPaused();
  EXPECT_TRUE(liveCamera_->locks.empty());
  EXPECT_FALSE(status.contains("exposure")) << status.dump();
  // Every frame reached the strobe (none was metered away). With an 8 ms exposure the frames
  // leave room for each switch, so about half are samples (2 on, 2 off); a switch the loop made
  // late (a loaded machine) costs a frame, never a label. A late switch also leaves the LED on
  // over more frames than the block's two, which are then rightly samples: the bound is the
  // strobe's, not the exact half (22 of 40 were seen under a load of 14 on two cores).
  EXPECT_EQ(status["camera_frames"]["delivered"], liveCamera_->frames) << status.dump();
  EXPECT_GT(status["sweep"]["samples"].get<int>(), 0) << status.dump();
  EXPECT_LE(status["sweep"]["samples"].get<int>(), liveCamera_->frames * 3 / 4) << status.dump();
}

TEST_F(DaemonOnFileCamera, StoppingTheDaemonMidSweepLeavesTheLedOff) {
  start();
  call(control::SessionNew{"grey card", std::string("grey")});
  call(control::SweepStart{kAxial3030});
  daemon_->stop();
  thread_.join();
  daemon_.reset();
  EXPECT_FALSE(ledLog().back().on);
}

TEST(DaemonSignals, EveryCatchableTerminatingSignalStopsTheDaemonAndSigpipeIsNot) {
  const std::vector<int> stops = stopSignals();
  for (const int s : {SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM,
                      SIGPROF, SIGXCPU, SIGIO, SIGPWR, SIGSTKFLT, SIGRTMIN, SIGRTMAX})
    EXPECT_NE(std::find(stops.begin(), stops.end(), s), stops.end()) << sigabbrev_np(s);
  // Faults of the process itself stay fatal; SIGPIPE and SIGXFSZ are ignored instead.
  for (const int s : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGPIPE, SIGXFSZ, SIGKILL})
    EXPECT_EQ(std::find(stops.begin(), stops.end(), s), stops.end()) << sigabbrev_np(s);
}

TEST_F(DaemonOnFileCamera, EachStopSignalSwitchesTheLedOffAndStopsCleanly) {
  // Only SIGTERM and SIGINT were handled: a dropped SSH session (SIGHUP) ended the daemon with
  // the LED lit. The signals are sent to this process: the daemon's loop has them blocked here
  // (its EventLoop blocks them in the thread that makes it, the thread it runs on inherits that).
  const std::vector<int> stops = stopSignals();
  for (const int s : {SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGTERM, SIGINT, SIGRTMIN}) {
    if (std::find(stops.begin(), stops.end(), s) == stops.end()) {
      ADD_FAILURE() << "signal " << s << " does not stop the daemon: not sent";
      continue;
    }
    liveCamera_ = std::make_shared<LiveCameraLog>();
    liveCamera_->frames = 100'000'000;  // captures until the signal
    liveCameraDevice_.reset();
    start();
    call(control::SessionNew{"grey card", std::string("grey")});
    call(control::SweepStart{kAxial3030});
    ASSERT_TRUE(ledWentOn()) << "the sweep never switched the LED on";
    ASSERT_EQ(::kill(::getpid(), s), 0);
    EXPECT_TRUE(stoppedWithin(20)) << "signal " << s << " did not stop the daemon";
    EXPECT_FALSE(ledLog().back().on) << "the LED is on after signal " << s;
    EXPECT_FALSE(liveCamera_->streaming) << "the camera was left streaming by signal " << s;
  }
}

TEST_F(DaemonOnFileCamera, SigpipeIsIgnored) {
  start();
  struct sigaction action {};
  ASSERT_EQ(::sigaction(SIGPIPE, nullptr, &action), 0);
  ASSERT_EQ(action.sa_handler, SIG_IGN) << "a client hanging up mid-write would end the daemon";
  ASSERT_EQ(::kill(::getpid(), SIGPIPE), 0);
  EXPECT_EQ(call(control::Status{})["state"].is_null(), call(control::Status{})["state"].is_null())
      << "still answering";
  EXPECT_FALSE(stopped_);
}

TEST_F(DaemonOnFileCamera, ExportsOnlyIntoTheStorageOrAFolderTheAskingUserOwns) {
  // The daemon writes with its own rights (root, or the slicecap user with its state folder): a
  // client must not make it write where the client itself could not.
  if (!test::canChangeUser()) GTEST_SKIP() << "needs root to run a client as another user";
  socketGroup_ = 0;  // the socket's group in slicecapd (ListenSocket::group)
  start();
  call(control::SessionNew{"grey card", std::string("grey")});
  ASSERT_EQ(::chmod(socketDir_.path().c_str(), 0711), 0);
  ASSERT_EQ(::chmod(socket_.c_str(), 0660), 0);  // the group's (root's, here) as in slicecapd
  const uid_t nobody = 65534;
  const auto exportAs = [&](const std::filesystem::path& directory) {
    return test::requestAsUser(socket_, nobody, 0, {},
                               control::encodeRequest({5, control::Export{std::nullopt, directory.string(), {}}}));
  };
  const std::filesystem::path roots = dir_ / "roots", theirs = dir_ / "theirs";
  std::filesystem::create_directories(roots);
  std::filesystem::create_directories(theirs);
  ASSERT_EQ(::chown(theirs.c_str(), nobody, nobody), 0);

  const std::string refused = exportAs(roots / "out");
  EXPECT_THAT(refused, HasSubstr("permission_denied")) << refused;
  EXPECT_THAT(refused, HasSubstr(roots.string())) << "names the folder";
  EXPECT_THAT(refused, HasSubstr("uid 65534")) << "names who asked";
  EXPECT_FALSE(std::filesystem::exists(roots / "out")) << "made before it was refused";
  // A link the client owns into a folder it does not own decides nothing: where it leads does.
  std::filesystem::create_directory_symlink(roots, theirs / "link");
  EXPECT_THAT(exportAs(theirs / "link"), HasSubstr("permission_denied"));
  EXPECT_THAT(exportAs(theirs / "link" / ".." / ".." / "roots"), HasSubstr("must not contain"));

  for (const auto& allowed : {theirs / "out", dir_ / "storage" / "grey" / "mine"}) {
    const std::string reply = exportAs(allowed);
    EXPECT_THAT(reply, Not(HasSubstr("permission_denied"))) << allowed << ": " << reply;
    EXPECT_THAT(reply, Not(HasSubstr("connect failed"))) << reply;
  }
  try {
    call(control::Export{std::nullopt, (roots / "out").string(), {}});
  } catch (const control::DaemonError& e) {
    EXPECT_NE(e.code(), "permission_denied") << "root may export anywhere: " << e.what();
  }
}

}  // namespace
}  // namespace slicecap::daemon
