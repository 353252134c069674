// record_frames: the recorder's queue never blocks and counts what it leaves out, a failed write
// stops only the recording, a continued sweep appends; and a sweep recorded by the daemon
// re-processes offline (slicecap process) into the samples the live sweep stored.
#include "slicecap/daemon/frame_recorder.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <fstream>
#include <limits>
#include <thread>

#include "../support/daemon_fakes.hpp"
#include "../support/test_support.hpp"
#include "../support/wait_until.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/control_client.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/daemon.hpp"
#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/hal/file_led.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::daemon {
namespace {

using nlohmann::json;

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};

io::Recording smallHeader() {
  io::Recording header;
  header.camera.intrinsics = {32, 24, 30.0, 30.0, 15.5, 11.5};
  header.target = vision::defaultTarget();
  header.slice = io::RecordedSlice{kAxial3030, kAxialOffsetDeg};
  return header;
}

hal::Frame smallFrame(std::int64_t timestampUs, bool ledOn) {
  hal::Frame frame;
  frame.image = {32, 24, 3, 8, std::vector<std::uint16_t>(32 * 24 * 3, ledOn ? 200 : 20)};
  frame.metadata.timestampUs = timestampUs;
  frame.metadata.exposureUs = 1000.0;
  frame.metadata.ledOn = ledOn;
  return frame;
}

TEST(FrameRecorder, AFullQueueDropsFramesFromTheRecordingAndCountsThemWithoutBlocking) {
  const auto dir = test::freshTempDir() / "rec";
  constexpr int kOffered = 200;
  std::size_t accepted = 0;
  RecorderStatus status;
  {
    FrameRecorder recorder(dir, smallHeader(), 1);
    for (int i = 0; i < kOffered; ++i)
      accepted += recorder.offer(smallFrame(1000 * i, i % 2 == 0));
    status = recorder.status();
  }  // the destructor writes what is queued
  EXPECT_GT(status.framesDropped, 0u) << "200 frames offered at once into a queue of one";
  EXPECT_EQ(accepted + status.framesDropped, std::size_t(kOffered));
  const io::Recording written = io::readRecording(dir);
  EXPECT_EQ(written.frames.size(), accepted);
  EXPECT_EQ(written.slice, smallHeader().slice);
  EXPECT_EQ(written.encoding, PixelEncoding::Srgb8);
}

TEST(FrameRecorder, AFailedWriteStopsTheRecordingWithItsReason) {
  const auto dir = test::freshTempDir();
  std::ofstream(dir / "file") << "not a folder";
  FrameRecorder recorder(dir / "file" / "rec", smallHeader());
  EXPECT_TRUE(recorder.offer(smallFrame(0, true)));
  ASSERT_TRUE(test::waitUntil([&] { return recorder.idle(); }))
      << "the recorder did not finish its queue of one frame within 10 s";
  const RecorderStatus status = recorder.status();
  EXPECT_NE(status.error.find((dir / "file" / "rec").string()), std::string::npos) << status.error;
  EXPECT_EQ(status.framesWritten, 0u);
  EXPECT_FALSE(recorder.offer(smallFrame(1, false))) << "a stopped recording takes no frames";
}

TEST(FrameRecorder, AContinuedSweepAppendsWithIncreasingTimestamps) {
  const auto dir = test::freshTempDir() / "rec";
  for (int run = 0; run < 2; ++run) {
    FrameRecorder recorder(dir, smallHeader(), 16);
    for (int i = 0; i < 3; ++i)
      ASSERT_TRUE(recorder.offer(smallFrame(1000 * i, i % 2 == 0)));  // the camera restarts at 0
  }
  const io::Recording written = io::readRecording(dir);  // checks the timestamps increase
  ASSERT_EQ(written.frames.size(), 6u);
  EXPECT_EQ(written.frames[2].timestampUs, 2000);
  EXPECT_EQ(written.frames[3].timestampUs, 2000 + 33333);
  EXPECT_EQ(written.frames[5].timestampUs, 2000 + 33333 + 2000);
}

// An HDR sweep's frames keep their exposure level in the recording (frames[].exposure_level), so
// that offline processing and the file camera see the levels the live sweep had.
TEST(FrameRecorder, RecordsEachFramesExposureLevel) {
  const auto dir = test::freshTempDir() / "rec";
  {
    FrameRecorder recorder(dir, smallHeader(), 16);
    for (int i = 0; i < 4; ++i) {
      hal::Frame frame = smallFrame(1000 * i, i % 2 == 0);
      frame.metadata.exposureLevel = i / 2;
      ASSERT_TRUE(recorder.offer(std::move(frame)));
    }
  }
  const io::Recording written = io::readRecording(dir);
  ASSERT_EQ(written.frames.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(written.frames[i].exposureLevel, std::optional(i / 2)) << i;
}

// The sweep run's decoding goes into recording.json; a continued sweep whose new bracket measured
// another curve cannot add its frames to the same recording: the recording stops, saying why.
TEST(FrameRecorder, RecordsTheSweepsDecodingAndRefusesToMixTwoCurves) {
  const auto dir = test::freshTempDir() / "rec";
  io::RecordedDecoding measured{io::RecordedDecoding::Kind::MeasuredCurve,
                                ToneCurve("measured", {{0.0, 0.0}, {0.2, 0.5}, {1.0, 1.0}})};
  {
    FrameRecorder recorder(dir, smallHeader(), 16);
    recorder.setDecoding(measured);
    ASSERT_TRUE(recorder.offer(smallFrame(1000, true)));
  }
  const io::Recording written = io::readRecording(dir);
  ASSERT_TRUE(written.decoding);
  EXPECT_EQ(*written.decoding, measured);
  {
    FrameRecorder recorder(dir, smallHeader(), 16);
    recorder.setDecoding(measured);  // the same curve (a continued run without a new bracket)
    ASSERT_TRUE(recorder.offer(smallFrame(2000, false)));
  }
  EXPECT_EQ(io::readRecording(dir).frames.size(), 2u);
  FrameRecorder recorder(dir, smallHeader(), 16);
  recorder.setDecoding({io::RecordedDecoding::Kind::MeasuredCurve,
                        ToneCurve("measured", {{0.0, 0.0}, {0.3, 0.5}, {1.0, 1.0}})});
  ASSERT_TRUE(recorder.offer(smallFrame(3000, true)));
  ASSERT_TRUE(test::waitUntil([&] { return recorder.idle(); }))
      << "the recorder did not finish its queue of one frame within 10 s";
  EXPECT_NE(recorder.status().error.find("one recording cannot hold both"), std::string::npos)
      << recorder.status().error;
  EXPECT_EQ(io::readRecording(dir).frames.size(), 2u);  // nothing recorded before is lost
}

// A continued sweep whose room-light gate changed (slicecapd.conf edited between its runs) cannot
// add to a recording offline processing reads with one gate: the recording stops, saying why.
TEST(FrameRecorder, RefusesToMixFramesOfTwoRoomLightGates) {
  const auto dir = test::freshTempDir() / "rec";
  io::Recording gated = smallHeader();
  gated.roomLightUnseenMm = 15.0;
  {
    FrameRecorder recorder(dir, gated, 16);
    ASSERT_TRUE(recorder.offer(smallFrame(1000, true)));
  }
  EXPECT_EQ(io::readRecording(dir).roomLightUnseenMm, std::optional<double>(15.0));
  {
    FrameRecorder recorder(dir, gated, 16);  // the same gate: appended
    ASSERT_TRUE(recorder.offer(smallFrame(2000, false)));
  }
  EXPECT_EQ(io::readRecording(dir).frames.size(), 2u);
  FrameRecorder recorder(dir, smallHeader(), 16);
  ASSERT_TRUE(recorder.offer(smallFrame(3000, true)));
  ASSERT_TRUE(test::waitUntil([&] { return recorder.idle(); }))
      << "the recorder did not finish its queue of one frame within 10 s";
  EXPECT_NE(recorder.status().error.find("room_light_unseen_mm = 15"), std::string::npos)
      << recorder.status().error;
  EXPECT_EQ(io::readRecording(dir).frames.size(), 2u);  // nothing recorded before is lost
}

TEST(FrameRecorder, ARawSweepsBlackIsRecordedAndReadBackWithItsFrames) {
  const auto dir = test::freshTempDir() / "rec";
  hal::Frame frame = smallFrame(1000, true);
  frame.encoding = PixelEncoding::Linear16;
  frame.black16 = hal::kDecodedBlack16;
  frame.image = {32, 24, 3, 16, std::vector<std::uint16_t>(32 * 24 * 3, 4000)};  // below black
  {
    FrameRecorder recorder(dir, smallHeader(), 16);
    recorder.setDecoding(io::RecordedDecoding::defaultFor(PixelEncoding::Linear16));
    ASSERT_TRUE(recorder.offer(hal::Frame(frame)));
  }
  const io::Recording written = io::readRecording(dir);
  ASSERT_TRUE(written.decoding);
  EXPECT_EQ(written.decoding->black16, hal::kDecodedBlack16);
  EXPECT_EQ(written.formatVersion, 3);  // a version 2 reader must not take the black for light
  // The file camera gives the frames back with their black.
  hal::SteadyClock clock;
  hal::FileCamera camera(dir, clock);
  hal::CameraConfig config{32, 24, PixelEncoding::Linear16, 1000.0, 1.0, 2};
  const hal::ConfigResult configured = camera.configure(config);
  ASSERT_NE(configured.status, hal::ConfigResult::Status::Invalid) << configured.reason;
  camera.start();
  const hal::CaptureResult read = camera.nextFrame(std::chrono::milliseconds(100));
  ASSERT_TRUE(read.frame);
  EXPECT_EQ(read.frame->black16, hal::kDecodedBlack16);
  EXPECT_LT(hal::linear16Value(read.frame->image.at(0, 0, 0), read.frame->black16), 0.0);
  // A later run whose frames are stored another way cannot continue it.
  FrameRecorder recorder(dir, smallHeader(), 16);
  frame.black16 = 0;
  frame.metadata.timestampUs = 2000;
  ASSERT_TRUE(recorder.offer(std::move(frame)));
  ASSERT_TRUE(test::waitUntil([&] { return recorder.idle(); }));
  EXPECT_NE(recorder.status().error.find("above a black of 4096"), std::string::npos)
      << recorder.status().error;
}

// The daemon records a simulated sweep played by the file camera through the real pipeline.
// record_frames as slicecapd's outputs do it: the played recording's camera and target.
class RecordingOutputs : public SessionOutputs {
 public:
  explicit RecordingOutputs(io::Recording played) : played_(std::move(played)) {}
  std::optional<io::Recording> recordingHeader(const SliceId&) override {
    io::Recording header;
    header.camera = played_.camera;
    header.target = played_.target;
    return header;
  }
  bool capturesTexture() const override { return false; }
  std::unique_ptr<TextureSink> openTexture(const SliceId&, const std::filesystem::path&,
                                           const std::vector<capture::SweepRefusal>&) override {
    return nullptr;
  }
  // No texture: a session's has nothing to set aside (these sessions never captured one).
  std::size_t settleTexture(const std::filesystem::path&,
                            const std::vector<capture::SweepRefusal>&) override {
    return 0;
  }

 private:
  io::Recording played_;
};

class DaemonRecordingFrames : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::freshTempDir();
    original_ = dir_ / "played";
    sim::SweepSetup setup;
    setup.rig = sim::RigParams::ideal();
    setup.rig.framesPerSlice = 12;
    setup.materialSpec = "ward:diffuse=0.3,0.2,0.1,specular=0.2,ax=0.2,ay=0.3,tangent=30";
    const sim::FrameRenderer renderer(setup.camera, setup.target,
                                      sim::loadMaterial(setup.materialSpec), setup.rig);
    sim::simulateSweep(original_, {kAxial3030, kAxialOffsetDeg}, renderer, setup);
    const io::Recording played = io::readRecording(original_);

    socket_ = socketDir_ / "s.sock";
    DaemonParts parts;
    parts.storage = dir_ / "storage";
    parts.rig = std::make_unique<test::OneCameraRig>(
        [this] { return std::make_shared<hal::FileCamera>(original_, clock_); },
        [played](capture::FrameObserver observer) {
          // As slicecapd's: two-sided room light, each LED-off frame located. The marker search
          // as offline's, as long as a frame takes: the live loop's budget spreads a search over
          // frames and moves the first pose of a sweep (0.2 deg here), which is not what this
          // compares.
          capture::PipelineSettings settings;
          settings.poseAmbientFrames = true;
          settings.detector.frameBudgetPx = std::numeric_limits<double>::infinity();
          return capture::makeLiveFramePipeline(played.target, played.camera, settings,
                                                std::move(observer));
        });
    parts.cameraConfig = {1280, 720, PixelEncoding::Srgb8, std::nullopt, std::nullopt, 4};
    parts.led = std::make_unique<hal::FileLed>(dir_ / "led.log", clock_);
    parts.tables = std::make_unique<test::EmptyTables>();
    parts.outputs = std::make_unique<RecordingOutputs>(played);
    parts.recordQueueFrames = 64;  // this test wants every frame; the bound has its own test
    daemon_ =
        std::make_unique<Daemon>(std::move(parts), openListenSocket({socket_, 0600, std::nullopt}));
    thread_ = std::thread([this] { daemon_->run(); });
  }

  void TearDown() override {
    daemon_->stop();
    thread_.join();
    daemon_.reset();
  }

  json call(const control::Command& command) { return control::ControlClient(socket_).call(command); }

  // Until the recording has been played and every queued frame written.
  json waitForRecording() {
    for (int attempt = 0; attempt < 3000; ++attempt) {
      json status = call(control::Status{});
      if (status["sweep"]["state"] == "paused" && status["recording"]["frames_queued"] == 0)
        return status;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "the sweep never finished recording";
    return call(control::Status{});
  }

  hal::SteadyClock clock_;
  test::SocketDir socketDir_;  // the socket path must fit sun_path
  std::filesystem::path dir_, original_, socket_;
  std::unique_ptr<Daemon> daemon_;
  std::thread thread_;
};

TEST_F(DaemonRecordingFrames, ProcessingTheRecordingGivesTheLiveSweepsSamples) {
  call(control::SessionNew{"ward", std::string("rec")});
  call(control::SweepStart{kAxial3030});
  const json status = waitForRecording();
  EXPECT_EQ(status["recording"]["frames_dropped"], 0);
  EXPECT_EQ(status["recording"]["frames_written"], 12);
  EXPECT_FALSE(status["recording"].contains("error"));
  const json stopped = call(control::SweepStop{});
  const auto recorded = std::filesystem::path(stopped["recording"]["directory"].get<std::string>());
  EXPECT_EQ(recorded, dir_ / "storage" / "rec" / "recordings" / "axial-30-30");

  // Every frame, LED on and off, pixel for pixel and with its metadata.
  const io::Recording original = io::readRecording(original_), copy = io::readRecording(recorded);
  ASSERT_EQ(copy.frames.size(), original.frames.size());
  EXPECT_EQ(copy.slice, original.slice);
  EXPECT_EQ(copy.camera, original.camera);
  for (std::size_t i = 0; i < copy.frames.size(); ++i) {
    EXPECT_EQ(copy.frames[i].ledOn, original.frames[i].ledOn);
    EXPECT_EQ(copy.frames[i].timestampUs, original.frames[i].timestampUs);
    EXPECT_EQ(io::readPng(io::framePath(recorded, copy.frames[i])).samples,
              io::readPng(io::framePath(original_, original.frames[i])).samples);
  }

  // slicecap process's default pipeline on the recording (two-sided room light, each LED-off
  // frame at its own pose): the live sweep's samples exactly, every one of them. The live loop
  // holds each LED-on frame until the LED-off frame after it arrives and makes the pipeline calls
  // processRecording makes, in the same order.
  const capture::RecordingResult offline = capture::processRecording(recorded);
  std::map<std::int64_t, capture::FrameSample> offlineSamples;
  for (const capture::FrameOutcome& outcome : offline.outcomes)
    if (outcome.sample) offlineSamples[outcome.sample->timestampUs] = *outcome.sample;
  const capture::SessionStore store = capture::SessionStore::open(dir_ / "storage", "rec");
  std::size_t live = 0;
  for (int bin = 0; bin < store.bins(kAxial3030).binCount(); ++bin) {
    for (const capture::FrameSample& sample : store.bins(kAxial3030).samplesIn(bin)) {
      ++live;
      const auto match = offlineSamples.find(sample.timestampUs);
      ASSERT_NE(match, offlineSamples.end()) << "frame at " << sample.timestampUs << " us";
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(match->second.value[c], sample.value[c], 1e-6 * std::abs(sample.value[c]));
      EXPECT_NEAR(match->second.view.thetaDeg, sample.view.thetaDeg, 1e-6);
      EXPECT_NEAR(match->second.view.phiDeg, sample.view.phiDeg, 1e-6);
      EXPECT_NEAR(match->second.light.phiDeg, sample.light.phiDeg, 1e-6);
    }
  }
  // The first LED-on frame too (it waits for the LED-off frame after it) and the last ones (the
  // stream's end settles them).
  EXPECT_EQ(offlineSamples.size(), live);
  EXPECT_GE(live, 4u);
}

}  // namespace
}  // namespace slicecap::daemon
