// What a sweep writes besides its samples: the raw-frame recording (record_frames) and the
// texture (texture capture). The daemon's capture devices feed them; they never stop a sample.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/daemon/daemon_parts.hpp"
#include "slicecap/daemon/frame_recorder.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/control/reply_views.hpp"

namespace slicecap::daemon {

/// \brief The swept slice's recorder and texture, opened, retired and discarded as the session
/// manager's sweep changes. Runs on the event loop; a recorder being retired writes its queue on
/// its own thread (destroying one waits for its writer, which the loop must not do).
class SweepOutputs {
 public:
  /// \brief `parts` and `manager` outlive this.
  SweepOutputs(const DaemonParts& parts, SessionManager& manager)
      : parts_(parts), manager_(manager) {}

  /// \brief Closes a texture of a slice no longer swept, settles the texture of a session just
  /// made current (SessionOutputs::settleTexture with its refusals), and opens the swept slice's
  /// while it captures (before its frames flow); one that cannot be opened pauses the sweep.
  void reconcileTexture();
  /// \brief One recorder per sweep of a slice: it lives while the sweep runs or is paused (a
  /// continued sweep appends to its recording) and retires when the sweep stops. A new one
  /// opens once the camera of `cameraSlice` runs.
  void reconcileRecorder(const std::optional<SliceId>& cameraSlice);

  /// \brief A redone sweep's texture starts afresh, as its samples: its folder is discarded
  /// durably before the redo is journaled. Throws io::IoError (the redo is then refused).
  void discardTexture(const SliceId& redone);
  /// \brief A sweep run begins: the texture's frames from now on are the run's.
  void beginTextureRun();
  /// \brief The run's texture frames so far (none without a texture), for its refusal's record.
  std::optional<capture::RunTextureFrames> textureRun() const;
  /// \brief The run ended unrefused: the earlier frames it replaced are deleted
  /// (TextureSink::keepRun); a failure is logged (they stay held, dropped when the session is
  /// next opened).
  void keepTextureRun();
  /// \brief The run was refused: its texture frames are set aside (TextureSink::setAsideRun).
  /// Returns a sentence for the status's error (empty without texture frames); a failure is
  /// logged and said there, never thrown (the refusal stands).
  std::string setAsideTextureRun();
  /// \brief A redone sweep starts its recording afresh, as its samples.
  void discardRecording(const SliceId& redone);

  /// \brief What the frame pipeline calls with each processed frame: the texture takes it.
  /// Empty without texture capture.
  capture::FrameObserver textureObserver();
  /// \brief A texture error met by the last frame pauses the sweep (the sample is kept).
  void pauseOnTextureError();
  /// \brief The frame goes to the recording, if one runs.
  void record(hal::Frame&& frame);
  /// \brief The sweep run's decoding, for the recording's header.
  void setDecoding(const io::RecordedDecoding& decoding);
  /// \brief A response bracket's frames, recorded under <session>/brackets/<slice>/run-N.
  void recordBracket(SweepDecoding& decided, const SliceId& slice);

  /// \brief The recording of the swept slice, for the status and the stop's reply.
  std::optional<control::RecordingView> recordingView() const;
  /// \brief The texture of the swept slice, for the status and the stop's reply.
  std::optional<control::TextureProgressView> textureView() const;

 private:
  bool capturesTexture() const;
  void closeTexture();
  void settleTexture();
  void openTexture(const SliceId& slice);
  static std::filesystem::path recordingDirectory(const std::filesystem::path& session,
                                                  const SliceId& slice);

  const DaemonParts& parts_;
  SessionManager& manager_;
  std::unique_ptr<FrameRecorder> recorder_;
  std::optional<SliceId> recorderSlice_;
  std::vector<std::unique_ptr<FrameRecorder>> retiredRecorders_;
  // The texture of the swept slice (while it runs or is paused), and the error its last frame
  // met (the frame loop pauses the sweep on it).
  std::unique_ptr<TextureSink> texture_;
  std::optional<SliceId> textureSlice_;
  std::string textureError_;
  // The session whose texture was settled last (settleTexture): each session made current once.
  std::optional<std::filesystem::path> settledSession_;
};

}  // namespace slicecap::daemon
