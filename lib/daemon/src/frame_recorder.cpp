// The record_frames writer thread: frames from the loop's queue into a recording on disk.
#include "slicecap/daemon/frame_recorder.hpp"

#include "slicecap/hal/recorded_frame.hpp"

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include "slicecap/daemon/slicecapd_error.hpp"

namespace slicecap::daemon {

struct FrameRecorder::State {
  std::filesystem::path directory;
  io::Recording header;
  std::size_t capacity;

  mutable std::mutex mutex;
  std::condition_variable wake;
  std::deque<hal::Frame> queue;
  bool writing = false;
  bool closing = false;
  std::size_t written = 0, dropped = 0;
  std::string error;
  std::optional<io::RecordedDecoding> decoding;  // set by the loop before the run's first frame

  // Writer thread only.
  std::optional<io::RecordingWriter> writer;
  std::int64_t timestampShiftUs = 0;
  std::thread thread;

  void open(const hal::Frame& first) {
    std::optional<io::RecordedDecoding> wanted;
    {
      std::lock_guard lock(mutex);
      wanted = decoding;
    }
    // A RAW sweep's frames hold their black above 0 (Frame::black16): the recording says so, or
    // a reader would take it for light; and one recording holds one black.
    if (first.encoding == PixelEncoding::Linear16) {
      if (!wanted) wanted = io::RecordedDecoding::defaultFor(first.encoding);
      wanted->black16 = first.black16;
    }
    if (std::filesystem::exists(directory / io::kRecordingManifest)) {
      writer.emplace(io::RecordingWriter::resume(directory));
      const io::Recording& held = writer->recording();
      if (held.encoding != first.encoding)
        throw SlicecapdError(
            directory.string() + " holds " + std::string(toString(held.encoding)) +
            " frames; the camera now delivers " + std::string(toString(first.encoding)));
      const io::RecordedDecoding heldDecoding =
          held.decoding.value_or(io::RecordedDecoding::defaultFor(held.encoding));
      const auto black = [](const io::RecordedDecoding& d) {
        return d.black16 != 0 ? " above a black of " + std::to_string(d.black16) : std::string();
      };
      if (wanted && !(*wanted == heldDecoding))
        throw SlicecapdError(
            directory.string() + " holds frames decoded as " + io::toString(heldDecoding.kind) +
            (heldDecoding.curve ? " (an earlier bracket's curve)" : "") + black(heldDecoding) +
            "; this sweep run decodes as " + io::toString(wanted->kind) +
            (wanted->curve ? " (its own bracket's curve)" : "") + black(*wanted) +
            ": one recording cannot hold both (redo the sweep to record it whole)");
      // Offline applies the recording's room-light gate to all its frames (offlineSettings).
      if (held.roomLightUnseenMm != header.roomLightUnseenMm) {
        const auto gate = [](const std::optional<double>& mm) {
          return mm ? "room_light_unseen_mm = " + std::to_string(*mm) : std::string("no room-light gate");
        };
        throw SlicecapdError(directory.string() + " holds frames captured with " +
                             gate(held.roomLightUnseenMm) + "; this sweep run has " +
                             gate(header.roomLightUnseenMm) +
                             ": one recording cannot hold both (redo the sweep to record it whole)");
      }
    } else {
      header.encoding = first.encoding;
      if (wanted) header.decoding = wanted;
      writer.emplace(directory, header);
    }
    std::lock_guard lock(mutex);
    written = writer->recording().frames.size();
  }

  void write(const hal::Frame& frame) {
    if (!writer) open(frame);
    const std::vector<io::RecordedFrame>& frames = writer->recording().frames;
    std::int64_t timestampUs = frame.metadata.timestampUs + timestampShiftUs;
    if (!frames.empty() && timestampUs <= frames.back().timestampUs) {
      // A camera started again counts from its own zero: continue one frame period on.
      constexpr std::int64_t kFramePeriodUs = 33333;
      timestampShiftUs += frames.back().timestampUs + kFramePeriodUs - timestampUs;
      timestampUs = frame.metadata.timestampUs + timestampShiftUs;
    }
    writer->append(frame.image, {"", timestampUs, frame.metadata.ledOn, frame.metadata.exposureUs,
                                 frame.metadata.gain,
                                 hal::recordedLedExposure(frame.metadata, timestampShiftUs),
                                 frame.metadata.exposureLevel});
  }

  void run() {
    std::unique_lock lock(mutex);
    for (;;) {
      wake.wait(lock, [this] { return closing || !queue.empty(); });
      if (queue.empty()) return;  // closing, and everything is written
      hal::Frame frame = std::move(queue.front());
      queue.pop_front();
      writing = true;
      lock.unlock();
      std::string failure;
      try {
        write(frame);
      } catch (const std::exception& e) {
        failure = e.what();
      }
      lock.lock();
      writing = false;
      if (failure.empty()) {
        ++written;
      } else {
        error = failure;
        queue.clear();
      }
    }
  }
};

FrameRecorder::FrameRecorder(std::filesystem::path directory, io::Recording header,
                             std::size_t queueFrames)
    : state_(std::make_unique<State>()) {
  state_->directory = std::move(directory);
  state_->header = std::move(header);
  state_->capacity = queueFrames;
  state_->thread = std::thread([s = state_.get()] { s->run(); });
}

FrameRecorder::~FrameRecorder() {
  {
    std::lock_guard lock(state_->mutex);
    state_->closing = true;
  }
  state_->wake.notify_one();
  state_->thread.join();
}

bool FrameRecorder::offer(hal::Frame&& frame) {
  {
    std::lock_guard lock(state_->mutex);
    if (!state_->error.empty()) return false;
    if (state_->queue.size() >= state_->capacity) {
      ++state_->dropped;
      return false;
    }
    state_->queue.push_back(std::move(frame));
  }
  state_->wake.notify_one();
  return true;
}

void FrameRecorder::setDecoding(const io::RecordedDecoding& decoding) {
  std::lock_guard lock(state_->mutex);
  state_->decoding = decoding;
}

RecorderStatus FrameRecorder::status() const {
  std::lock_guard lock(state_->mutex);
  return {state_->directory, state_->written, state_->queue.size() + (state_->writing ? 1 : 0),
          state_->dropped, state_->error};
}

bool FrameRecorder::idle() const {
  std::lock_guard lock(state_->mutex);
  return state_->queue.empty() && !state_->writing;
}

}  // namespace slicecap::daemon
