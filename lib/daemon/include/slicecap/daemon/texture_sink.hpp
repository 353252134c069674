// The daemon's texture capture behind an interface: lib/daemon decides when a sweep's frames go to
// a texture; how frames become stored texels is lib/rig's StoreTextureSink (over lib/btf).
#pragma once

#include <vector>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::daemon {

/// \brief The folder of a session where its texture is kept, one sub-folder per slice named by
/// folderName(SliceId) (what a redone sweep discards, whether or not texture capture is on).
inline constexpr const char* kTextureFolder = "texture";

/// \brief One slice's texture capture in a session (texture_resolution set).
class TextureSink {
 public:
  virtual ~TextureSink() = default;
  /// \brief One frame of the running sweep, after the pipeline, with the room-light term it used
  /// (capture::FrameObserver). Durable when this returns. Throws io::IoError when the texture
  /// cannot be stored (the daemon then pauses the sweep; the window samples are not affected).
  virtual void add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
                   const std::vector<capture::AmbientTerm>& ambient) = 0;
  /// \brief What the status shows of the slice's texture (the store's figures where it has them).
  virtual control::TextureProgressView status() const = 0;
  /// \brief A sweep run begins (its camera starts): the frames stored from now on are the run's,
  /// and the frames of earlier runs they replace are held until the run is judged.
  virtual void beginRun() = 0;
  /// \brief The run's frames so far, as the store numbers them (what a refusal records).
  virtual capture::RunTextureFrames run() const = 0;
  /// \brief The run was kept (it ended unrefused): the earlier frames it replaced are deleted.
  /// Throws io::IoError when they cannot be (they stay held; opening the session drops them).
  virtual void keepRun() = 0;
  /// \brief The run was refused (its samples set aside): its stored frames are set aside too,
  /// into the slice's folder + io::kSetAsideSuffix (kept, read by nothing, exported by nothing),
  /// and the earlier frames they replaced go back, so the texture holds the slice's other runs
  /// alone. Returns how many were set aside; throws io::IoError when they cannot be moved.
  virtual std::size_t setAsideRun() = 0;
};

}  // namespace slicecap::daemon
