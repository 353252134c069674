// What a sweep keeps besides its samples, as slicecapd.conf asks.
#include "configured_outputs.hpp"

#include "store_texture_sink.hpp"

#include "slicecap/btf/texture_store.hpp"

namespace slicecap::rig {
namespace {

// The refusals that name texture frames, as the texture store takes them.
std::vector<btf::TextureRun> textureRuns(const std::vector<capture::SweepRefusal>& refused) {
  std::vector<btf::TextureRun> runs;
  for (const capture::SweepRefusal& refusal : refused)
    if (refusal.textureFrames)
      runs.push_back({refusal.slice, refusal.textureFrames->from, refusal.textureFrames->to});
  return runs;
}

}  // namespace

OutputSettings outputSettingsFrom(const daemon::DaemonConfig& config) {
  return {config.recordFrames, config.textureResolution, config.textureFramesPerBin,
          config.roomLightUnseenMm};
}

ConfiguredSessionOutputs::ConfiguredSessionOutputs(const OutputSettings& settings,
                                                   std::function<Rig(const SliceId&)> rigFor,
                                                   std::string createdBy)
    : recordFrames_(settings.recordFrames),
      textureResolution_(settings.textureResolution),
      textureFramesPerBin_(settings.textureFramesPerBin),
      roomLightUnseenMm_(settings.roomLightUnseenMm),
      rigFor_(std::move(rigFor)),
      createdBy_(std::move(createdBy)) {}

std::optional<io::Recording> ConfiguredSessionOutputs::recordingHeader(const SliceId& slice) {
  if (!recordFrames_) return std::nullopt;
  const Rig rig = rigFor_(slice);
  io::Recording header;
  header.createdBy = createdBy_;
  header.camera = rig.camera;
  header.target = rig.target;
  if (roomLightUnseenMm_ > 0.0) header.roomLightUnseenMm = roomLightUnseenMm_;
  return header;
}

std::unique_ptr<daemon::TextureSink> ConfiguredSessionOutputs::openTexture(
    const SliceId& slice, const std::filesystem::path& session,
    const std::vector<capture::SweepRefusal>& refused) {
  const Rig rig = rigFor_(slice);
  return std::make_unique<StoreTextureSink>(
      session / daemon::kTextureFolder, slice, rig.camera,
      btf::TextureStoreLayout{textureResolution_, rig.target.window, textureFramesPerBin_},
      textureRuns(refused));
}

std::size_t ConfiguredSessionOutputs::settleTexture(
    const std::filesystem::path& session, const std::vector<capture::SweepRefusal>& refused) {
  const std::filesystem::path texture = session / daemon::kTextureFolder;
  // A session without a texture has nothing to settle; one captured with texture on is settled
  // whatever the configuration says now (its frames are the session's).
  if (!std::filesystem::exists(texture / btf::kTextureStoreManifest)) return 0;
  const std::vector<btf::TextureRun> runs = textureRuns(refused);
  btf::TextureStore store = btf::TextureStore::open(texture, btf::StoreAccess::Mend, runs);
  logTextureRecovery(store);
  return store.settleRuns(runs);
}

}  // namespace slicecap::rig
