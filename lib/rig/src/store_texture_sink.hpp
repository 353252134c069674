// The daemon's TextureSink on lib/btf's texture store in the session's folder.
#pragma once

#include <filesystem>

#include "slicecap/btf/texture_capture.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::rig {

/// \brief Logs what opening `store` mended after a crash (the journal under systemd).
void logTextureRecovery(const btf::TextureStore& store);

/// \brief One slice's texture in a session's texture store (btf::TextureSweep). What opening the
/// store mended after a crash is logged (the journal under systemd).
class StoreTextureSink final : public daemon::TextureSink {
 public:
  /// \brief Throws what btf::TextureSweep throws (io::IoError naming the folder, or a store of
  /// another layout). `refused`: the session's refused runs, applied as the store opens.
  StoreTextureSink(const std::filesystem::path& directory, const SliceId& slice,
                   const vision::CameraModel& camera, const btf::TextureStoreLayout& layout,
                   const std::vector<btf::TextureRun>& refused = {});

  void add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
           const std::vector<capture::AmbientTerm>& ambient) override;
  control::TextureProgressView status() const override;
  void beginRun() override { sweep_.beginRun(); }
  capture::RunTextureFrames run() const override;
  void keepRun() override { sweep_.keepRun(); }
  std::size_t setAsideRun() override { return sweep_.setAsideRun(); }

 private:
  btf::TextureSweep sweep_;
};

}  // namespace slicecap::rig
