// Raw frames of a sweep kept as a recording (record_frames): a bounded queue and a writer thread,
// so writing PNGs (~50 ms a 720p frame) never holds up the frame loop.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include "slicecap/hal/frame.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::daemon {

/// \brief What a recorder has done so far.
struct RecorderStatus {
  std::filesystem::path directory;
  std::size_t framesWritten = 0;  ///< in the recording on disk, manifest included
  std::size_t framesQueued = 0;   ///< waiting for the writer
  /// Offered while the queue was full, so left out of the recording (never out of the sweep).
  std::size_t framesDropped = 0;
  /// Why recording stopped (a full disk, a frame the recording cannot hold); empty while it runs.
  std::string error;
};

/// \brief Writes the frames a sweep's camera delivers (LED on and off) into one recording
/// (io::RecordingWriter: a crash loses at most the frame being written). The recording's
/// directory is created, or continued when it holds one already (a paused sweep going on, a
/// restarted daemon), on the first frame; timestamps that do not increase (a camera started
/// again) are shifted past the last recorded one. Any write failure stops the recording with
/// `error` set; the caller's sweep goes on.
class FrameRecorder {
 public:
  /// \brief `header` gives the camera, target and slice (its frames must be empty; its encoding
  /// is replaced by the first frame's). Starts the writer thread; touches no file yet.
  FrameRecorder(std::filesystem::path directory, io::Recording header, std::size_t queueFrames = 4);
  /// \brief Writes what is queued, then stops the writer.
  ~FrameRecorder();
  FrameRecorder(const FrameRecorder&) = delete;
  FrameRecorder& operator=(const FrameRecorder&) = delete;

  /// \brief Never blocks: queues the frame (taking its pixels) if there is room and the recording
  /// has not stopped; otherwise counts it dropped (when full) and returns false.
  bool offer(hal::Frame&& frame);
  /// \brief How this sweep run's frames decode (issue 27: the bracket's fit, or why sRGB), for
  /// the recording's `decoding`; call it before the run's first offer(). A recording continued
  /// from an earlier run that decoded otherwise (every bracket fits its own curve) cannot hold
  /// both: the recording stops with an error saying so, and the sweep goes on.
  void setDecoding(const io::RecordedDecoding& decoding);
  RecorderStatus status() const;
  /// \brief True when nothing is queued or being written.
  bool idle() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::daemon
