// The daemon's SessionOutputs from slicecapd.conf: record_frames' recording header and
// texture_resolution's texture store.
#pragma once

#include <functional>
#include <string>

#include "slicecap/daemon/session_outputs.hpp"
#include "slicecap/rig/configured_devices.hpp"

namespace slicecap::rig {

/// \brief What slicecapd.conf asks a sweep to keep: record_frames, texture_resolution,
/// texture_frames_per_bin; and room_light_unseen_mm, which a recording carries so that offline
/// processing gates its frames as the sweep did.
struct OutputSettings {
  bool recordFrames = false;
  int textureResolution = 0;
  int textureFramesPerBin = 0;
  double roomLightUnseenMm = 0.0;
};

/// \brief The configuration's OutputSettings.
OutputSettings outputSettingsFrom(const daemon::DaemonConfig& config);

/// \brief What the configuration keeps of a sweep besides its samples.
class ConfiguredSessionOutputs final : public daemon::SessionOutputs {
 public:
  /// \brief `rigFor`: each slice's target and camera model (CameraSources::rigFor); `createdBy`:
  /// the recordings' creator ("slicecapd 1.2 (model camera)").
  ConfiguredSessionOutputs(const OutputSettings& settings, std::function<Rig(const SliceId&)> rigFor,
                           std::string createdBy);

  std::optional<io::Recording> recordingHeader(const SliceId& slice) override;
  bool capturesTexture() const override { return textureResolution_ > 0; }
  std::unique_ptr<daemon::TextureSink> openTexture(
      const SliceId& slice, const std::filesystem::path& session,
      const std::vector<capture::SweepRefusal>& refused) override;
  std::size_t settleTexture(const std::filesystem::path& session,
                            const std::vector<capture::SweepRefusal>& refused) override;

 private:
  bool recordFrames_;
  int textureResolution_;
  int textureFramesPerBin_;
  double roomLightUnseenMm_;
  std::function<Rig(const SliceId&)> rigFor_;
  std::string createdBy_;
};

}  // namespace slicecap::rig
