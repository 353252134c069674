// The daemon's second collaborator: what a sweep keeps besides its samples (the raw frames under
// record_frames, the texture under texture_resolution). lib/rig builds it from slicecapd.conf.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "slicecap/core/slice.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::daemon {

/// \brief The recording header and the texture of each slice's sweep. Called on the event loop.
class SessionOutputs {
 public:
  virtual ~SessionOutputs() = default;

  /// \brief record_frames: the recording header (camera model, target, creator) of a sweep of
  /// `slice`; every frame of the sweep is then kept in <session>/recordings/<slice>
  /// (FrameRecorder), its bracket frames in <session>/brackets. nullopt: no frames are kept.
  virtual std::optional<io::Recording> recordingHeader(const SliceId& slice) = 0;

  /// \brief Whether sweeps capture a texture (openTexture is then asked at each sweep start).
  virtual bool capturesTexture() const = 0;
  /// \brief The texture of a sweep of `slice`, stored in <session>/texture (kTextureFolder).
  /// Throws (a std::exception with a message) when it cannot be opened, e.g. the session's
  /// texture has another resolution; the sweep then pauses. `refused`: the session's refusals,
  /// applied at every opening before the keep rule (frames a failed set-aside left in the
  /// texture never cost a kept frame) and numbered past.
  virtual std::unique_ptr<TextureSink> openTexture(
      const SliceId& slice, const std::filesystem::path& session,
      const std::vector<capture::SweepRefusal>& refused) = 0;
  /// \brief A session was made current: its texture (in <session>/kTextureFolder, whether or not
  /// sweeps capture one now), if it has one, sets aside again the frames of every run in
  /// `refused` that names them (a crash between the journal's refusal and the move left them in
  /// the texture), puts back the frames those runs replaced, and deletes the frames a run cut
  /// off before it was judged replaced (such a run counts as kept). Idempotent. Returns the
  /// frames set aside now; throws (a std::exception with a message) when the texture cannot be
  /// read or its files moved.
  virtual std::size_t settleTexture(const std::filesystem::path& session,
                                    const std::vector<capture::SweepRefusal>& refused) = 0;
};

}  // namespace slicecap::daemon
