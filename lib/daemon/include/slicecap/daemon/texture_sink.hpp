// The daemon's texture capture behind an interface: lib/daemon decides when a sweep's frames go to
// a texture; how frames become stored texels is lib/rig's StoreTextureSink (over lib/btf).
#pragma once

#include <vector>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
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
  /// \brief A sweep run begins (its camera starts): the frames stored from now on are the run's.
  virtual void beginRun() = 0;
  /// \brief The run was refused (its samples set aside): its stored frames are set aside too,
  /// into the slice's folder + io::kSetAsideSuffix (kept, read by nothing, exported by nothing),
  /// so the texture holds the slice's other runs alone. Returns how many; throws io::IoError
  /// when they cannot be moved.
  virtual std::size_t setAsideRun() = 0;
};

}  // namespace slicecap::daemon
