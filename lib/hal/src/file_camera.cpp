// Playing a recording as a camera: frames in order, paced on the clock if asked, errors as values.
#include "slicecap/hal/file_camera.hpp"

#include <algorithm>
#include <stdexcept>

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/hal/camera_error.hpp"
#include "slicecap/hal/recorded_frame.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::hal {

struct FileCamera::State {
  std::filesystem::path directory;
  io::Recording recording;
  Clock& clock;
  FileCameraOptions options;
  bool configured = false;
  bool running = false;
  std::uint64_t sequence = 0;
  std::int64_t startUs = 0;
  std::int64_t periodUs = 0;  // the loop adds this after the last frame
};

FileCamera::FileCamera(const std::filesystem::path& recording, Clock& clock,
                       FileCameraOptions options)
    : state_(new State{recording, io::readRecording(recording), clock, options}) {
  const auto& frames = state_->recording.frames;
  if (frames.empty()) throw io::IoError(recording.string() + ": the recording has no frames");
  // Outside it a frame's due time overflows the clock's microseconds.
  if (!(options.speed >= 0.01 && options.speed <= 1000.0))
    throw CameraError(recording.string() + ": a playing speed of " +
                      std::to_string(options.speed) + " is not in 0.01..1000");
  // The frames' exposure levels as offline processing (processRecording) reads them: a recording
  // with no level above 0 is of one exposure (no levels at all), and in an HDR one a frame
  // without a level is at level 0.
  const bool hdr = std::any_of(frames.begin(), frames.end(), [](const io::RecordedFrame& f) {
    return f.exposureLevel.value_or(0) > 0;
  });
  for (io::RecordedFrame& f : state_->recording.frames)
    f.exposureLevel = hdr ? std::optional(f.exposureLevel.value_or(0)) : std::nullopt;
  state_->periodUs = frames.size() > 1 ? (frames.back().timestampUs - frames.front().timestampUs) /
                                             static_cast<std::int64_t>(frames.size() - 1)
                                       : 33333;
  if (std::filesystem::is_regular_file(recording)) state_->directory = recording.parent_path();
}

FileCamera::~FileCamera() = default;

std::string FileCamera::id() const {
  return "file:" + state_->directory.string();
}

std::size_t FileCamera::frameCount() const {
  return state_->recording.frames.size();
}

ConfigResult FileCamera::configure(CameraConfig& config) {
  if (state_->running) throw std::logic_error("FileCamera::configure while running");
  const vision::CameraIntrinsics& k = state_->recording.camera.intrinsics;
  std::string adjusted;
  if (config.widthPx != k.widthPx || config.heightPx != k.heightPx) {
    adjusted += "size set to the recording's " + std::to_string(k.widthPx) + " x " +
                std::to_string(k.heightPx) + "; ";
    config.widthPx = k.widthPx;
    config.heightPx = k.heightPx;
  }
  if (config.encoding != state_->recording.encoding) {
    adjusted += "encoding set to the recording's " +
                std::string(toString(state_->recording.encoding)) + "; ";
    config.encoding = state_->recording.encoding;
  }
  if (config.exposureUs || config.gain) {
    adjusted += "exposure and gain are the recording's own; ";
    config.exposureUs.reset();
    config.gain.reset();
  }
  state_->configured = true;
  if (adjusted.empty()) return {ConfigResult::Status::Valid, ""};
  adjusted.resize(adjusted.size() - 2);
  return {ConfigResult::Status::Adjusted, adjusted};
}

void FileCamera::start() {
  if (!state_->configured) throw std::logic_error("FileCamera::start before configure");
  state_->running = true;
  state_->sequence = 0;
  state_->startUs = state_->clock.nowUs();
}

void FileCamera::stop() {
  state_->running = false;
}

CaptureResult FileCamera::nextFrame(std::chrono::milliseconds timeout) {
  State& s = *state_;
  if (!s.running) throw std::logic_error("FileCamera::nextFrame before start");
  const auto& frames = s.recording.frames;
  const std::uint64_t pass = s.sequence / frames.size();
  if (pass > 0 && !s.options.loop) return {CaptureResult::Status::EndOfStream, std::nullopt, ""};
  const io::RecordedFrame& entry = frames[s.sequence % frames.size()];
  const std::int64_t span = frames.back().timestampUs - frames.front().timestampUs + s.periodUs;
  const std::int64_t timestampUs = entry.timestampUs + static_cast<std::int64_t>(pass) * span;
  if (s.options.paced) {
    const std::int64_t dueUs =
        s.startUs + static_cast<std::int64_t>(double(timestampUs - frames.front().timestampUs) /
                                              s.options.speed);
    const std::int64_t deadlineUs = s.clock.nowUs() + timeout.count() * 1000;
    if (dueUs > deadlineUs) {
      s.clock.sleepUntilUs(deadlineUs);
      return {CaptureResult::Status::Timeout, std::nullopt, ""};
    }
    s.clock.sleepUntilUs(dueUs);
  }
  const std::uint64_t sequence = s.sequence++;
  const std::filesystem::path file = io::framePath(s.directory, entry);
  if (s.options.failAtSequence && *s.options.failAtSequence == sequence)
    return {CaptureResult::Status::Error, std::nullopt,
            file.string() + ": injected camera failure"};
  Frame frame;
  try {
    frame.image = io::readPng(file);
  } catch (const io::IoError& e) {
    return {CaptureResult::Status::Error, std::nullopt, e.what()};
  }
  const vision::CameraIntrinsics& k = s.recording.camera.intrinsics;
  if (frame.image.width != k.widthPx || frame.image.height != k.heightPx ||
      frame.image.bitDepth != bitDepthOf(s.recording.encoding) ||
      (frame.image.channels != 1 && frame.image.channels != 3))
    return {CaptureResult::Status::Error, std::nullopt,
            file.string() + ": a " + std::to_string(frame.image.width) + " x " +
                std::to_string(frame.image.height) + " image of " +
                std::to_string(frame.image.channels) + " channel(s), " +
                std::to_string(frame.image.bitDepth) + "-bit, where the recording says " +
                std::to_string(k.widthPx) + " x " + std::to_string(k.heightPx) + " " +
                std::string(toString(s.recording.encoding)) + " gray or RGB"};
  setRecordedEncoding(frame, s.recording);
  frame.metadata = metadataOf(entry, sequence, timestampUs - entry.timestampUs);
  return {CaptureResult::Status::Frame, std::move(frame), ""};
}

}  // namespace slicecap::hal
