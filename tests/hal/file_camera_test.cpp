// The file camera plays a recording with its timestamps and metadata, paced or not, looping, and
// reports bad frames and calls out of order.
#include "slicecap/hal/file_camera.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "../support/test_support.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::hal {
namespace {

using namespace std::chrono_literals;

// Three 8 x 6 RGB frames, 40 ms apart from t = 1 s, alternating LED, the third at gain 2.
std::filesystem::path threeFrameRecording() {
  const auto dir = test::freshTempDir() / "rec";
  io::Recording header;
  header.camera.intrinsics = {8, 6, 10.0, 10.0, 3.5, 2.5};
  header.target = vision::defaultTarget();
  io::RecordingWriter writer(dir, header);
  for (int i = 0; i < 3; ++i) {
    Image image{8, 6, 3, 8,
                std::vector<std::uint16_t>(8 * 6 * 3, static_cast<std::uint16_t>(10 * i))};
    writer.append(image, {"", 1'000'000 + 40'000 * i, i % 2 == 0, 2000.0 + i, i == 2 ? 2.0 : 1.0});
  }
  return dir;
}

TEST(FileCamera, PlaysEveryFrameWithItsTimestampAndMetadataThenEnds) {
  FakeClock clock;
  FileCamera camera(threeFrameRecording(), clock);
  CameraConfig config;
  EXPECT_EQ(camera.configure(config).status, ConfigResult::Status::Adjusted);
  EXPECT_EQ(config.widthPx, 8);
  EXPECT_EQ(camera.configure(config).status, ConfigResult::Status::Valid);
  camera.start();
  for (int i = 0; i < 3; ++i) {
    const CaptureResult r = camera.nextFrame(100ms);
    ASSERT_EQ(r.status, CaptureResult::Status::Frame) << r.error;
    EXPECT_EQ(r.frame->metadata.sequence, std::uint64_t(i));
    EXPECT_EQ(r.frame->metadata.timestampUs, 1'000'000 + 40'000 * i);
    EXPECT_EQ(r.frame->metadata.ledOn, i % 2 == 0);
    EXPECT_EQ(r.frame->metadata.exposureUs, 2000.0 + i);
    EXPECT_EQ(r.frame->metadata.gain, i == 2 ? 2.0 : 1.0);
    EXPECT_EQ(r.frame->image.at(7, 5, 2), 10 * i);
  }
  EXPECT_EQ(camera.nextFrame(100ms).status, CaptureResult::Status::EndOfStream);
}

// A recording of frames at `levels` (nullopt: no exposure_level written).
std::filesystem::path levelledRecording(const std::vector<std::optional<int>>& levels) {
  const auto dir = test::freshTempDir() / "levels";
  io::Recording header;
  header.camera.intrinsics = {8, 6, 10.0, 10.0, 3.5, 2.5};
  header.target = vision::defaultTarget();
  io::RecordingWriter writer(dir, header);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    Image image{8, 6, 3, 8, std::vector<std::uint16_t>(8 * 6 * 3, 50)};
    io::RecordedFrame entry{"", 1'000'000 + 40'000 * std::int64_t(i), i % 2 == 0, 2000.0, 1.0};
    entry.exposureLevel = levels[i];
    writer.append(image, entry);
  }
  return dir;
}

std::vector<std::optional<int>> playedLevels(const std::filesystem::path& recording) {
  FakeClock clock;
  FileCamera camera(recording, clock);
  CameraConfig config;
  camera.configure(config);
  camera.start();
  std::vector<std::optional<int>> levels;
  for (CaptureResult r = camera.nextFrame(100ms); r.status == CaptureResult::Status::Frame;
       r = camera.nextFrame(100ms))
    levels.push_back(r.frame->metadata.exposureLevel);
  return levels;
}

// The frames' exposure levels as offline processing reads them: an HDR recording's levels (a frame
// without one at level 0), and none for a recording whose frames all say level 0.
TEST(FileCamera, PlaysAnHdrRecordingsExposureLevelsAsOfflineProcessingReadsThem) {
  using Levels = std::vector<std::optional<int>>;
  EXPECT_EQ(playedLevels(levelledRecording({0, 0, 1, 1, std::nullopt, 0})),
            (Levels{0, 0, 1, 1, 0, 0}));
  EXPECT_EQ(playedLevels(levelledRecording({0, 0, 0, 0})), (Levels(4, std::nullopt)));
  EXPECT_EQ(playedLevels(levelledRecording({std::nullopt, std::nullopt})),
            (Levels(2, std::nullopt)));
}

TEST(FileCamera, PacedPlaybackWaitsOnTheClockAndTimesOut) {
  FakeClock clock(500);
  FileCameraOptions options;
  options.paced = true;
  FileCamera camera(threeFrameRecording(), clock, options);
  CameraConfig config;
  config.widthPx = 8;
  config.heightPx = 6;
  camera.configure(config);
  camera.start();
  EXPECT_EQ(camera.nextFrame(0ms).status, CaptureResult::Status::Frame);
  EXPECT_EQ(clock.nowUs(), 500);
  // The next frame is due 40 ms after the first: a 10 ms wait times out, a longer one gets it.
  EXPECT_EQ(camera.nextFrame(10ms).status, CaptureResult::Status::Timeout);
  EXPECT_EQ(camera.nextFrame(100ms).status, CaptureResult::Status::Frame);
  EXPECT_EQ(clock.nowUs(), 500 + 40'000);
}

TEST(FileCamera, PlayedFasterItsFramesComeSoonerWithTheirRecordedTimestamps) {
  FakeClock clock(500);
  FileCameraOptions options;
  options.paced = true;
  options.speed = 4.0;
  FileCamera camera(threeFrameRecording(), clock, options);
  CameraConfig config;
  config.widthPx = 8;
  config.heightPx = 6;
  camera.configure(config);
  camera.start();
  const CaptureResult first = camera.nextFrame(0ms);
  ASSERT_EQ(first.status, CaptureResult::Status::Frame);
  // 40 ms of the recording are 10 ms of the clock: a 5 ms wait times out, a 10 ms one gets it,
  // and its timestamp is still the recorded one, 40 ms after the first's.
  EXPECT_EQ(camera.nextFrame(5ms).status, CaptureResult::Status::Timeout);
  const CaptureResult second = camera.nextFrame(10ms);
  ASSERT_EQ(second.status, CaptureResult::Status::Frame);
  EXPECT_EQ(clock.nowUs(), 500 + 10'000);
  EXPECT_EQ(second.frame->metadata.timestampUs - first.frame->metadata.timestampUs, 40'000);
}

TEST(FileCamera, LoopsWithIncreasingTimestampsAndReportsBadFramesAsErrors) {
  FakeClock clock;
  const auto dir = threeFrameRecording();
  FileCameraOptions options;
  options.loop = true;
  options.failAtSequence = 4;
  FileCamera camera(dir, clock, options);
  CameraConfig config;
  config.widthPx = 8;
  config.heightPx = 6;
  camera.configure(config);
  camera.start();
  std::int64_t previous = 0;
  for (int i = 0; i < 4; ++i) {
    const CaptureResult r = camera.nextFrame(0ms);
    ASSERT_EQ(r.status, CaptureResult::Status::Frame);
    EXPECT_GT(r.frame->metadata.timestampUs, previous);
    previous = r.frame->metadata.timestampUs;
  }
  EXPECT_EQ(previous, 1'000'000 + 120'000);  // the loop goes on at the recording's frame period
  const CaptureResult injected = camera.nextFrame(0ms);
  EXPECT_EQ(injected.status, CaptureResult::Status::Error);
  EXPECT_NE(injected.error.find("frame-00001.png"), std::string::npos) << injected.error;
  std::ofstream(dir / "frame-00002.png") << "not a png";
  const CaptureResult corrupt = camera.nextFrame(0ms);
  EXPECT_EQ(corrupt.status, CaptureResult::Status::Error);
  EXPECT_NE(corrupt.error.find("frame-00002.png"), std::string::npos) << corrupt.error;
  EXPECT_EQ(camera.nextFrame(0ms).status, CaptureResult::Status::Frame);  // playback goes on
}

TEST(FileCamera, RefusesCallsOutOfOrderAndNamesAMissingRecording) {
  FakeClock clock;
  FileCamera camera(threeFrameRecording(), clock);
  EXPECT_THROW(camera.start(), std::logic_error);
  EXPECT_THROW(camera.nextFrame(0ms), std::logic_error);
  const auto missing = test::freshTempDir() / "nothing-here";
  try {
    FileCamera none(missing, clock);
    FAIL() << "a missing recording was accepted";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing-here"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slicecap::hal
