// A camera that plays a recording frame by frame, with its timestamps and metadata.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"

namespace slicecap::hal {

/// \brief How a recording is played.
struct FileCameraOptions {
  /// Deliver each frame no earlier than its recorded time after start() (on the clock), as a live
  /// camera would; false: as fast as asked.
  bool paced = false;
  /// With paced: the recording's time runs this many times faster than the clock (1: as
  /// recorded; 0.01..1000, else the constructor throws CameraError). The frames and their
  /// timestamps are the recorded ones whatever the speed.
  double speed = 1.0;
  /// Start over after the last frame; timestamps keep increasing by the recording's frame period.
  bool loop = false;
  /// Fault injection for tests: the frame of this sequence number comes back as an Error.
  std::optional<std::uint64_t> failAtSequence;
};

/// \brief Plays a recording directory (io::readRecording validates it in the constructor, which
/// throws io::IoError naming the field). Frames whose PNG is missing, corrupt or of the wrong
/// size come back as CaptureResult::Error naming the file, and playback goes on with the next.
class FileCamera final : public Camera {
 public:
  FileCamera(const std::filesystem::path& recording, Clock& clock, FileCameraOptions options = {});
  ~FileCamera() override;

  std::string id() const override;
  /// \brief Valid when `config` asks for the recording's size and encoding with exposure and gain
  /// unset; otherwise Adjusted to those (a recording's exposure is what it was).
  ConfigResult configure(CameraConfig& config) override;
  void start() override;
  void stop() override;
  CaptureResult nextFrame(std::chrono::milliseconds timeout) override;

  /// \brief Frames in the recording (one pass).
  std::size_t frameCount() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::hal
