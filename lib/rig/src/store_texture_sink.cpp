// A slice's texture capture on the session's texture store (docs/btf-format.md).
#include "store_texture_sink.hpp"

#include <iostream>

namespace slicecap::rig {

void logTextureRecovery(const btf::TextureStore& store) {
  // What opening mended after a crash goes to the journal (stderr under systemd).
  const btf::TextureStoreRecovery& recovery = store.recovery();
  for (const std::string& dropped : recovery.droppedFiles)
    std::cerr << "slicecapd: texture: removed a damaged frame: " << dropped << "\n";
  if (recovery.leftovers > 0)
    std::cerr << "slicecapd: texture: removed " << recovery.leftovers << " leftovers of an "
              << "interrupted write or redo in " << store.directory().string() << "\n";
}

StoreTextureSink::StoreTextureSink(const std::filesystem::path& directory, const SliceId& slice,
                                   const vision::CameraModel& camera,
                                   const btf::TextureStoreLayout& layout,
                                   const std::vector<btf::TextureRun>& refused)
    : sweep_(directory, slice, camera, layout, {}, refused) {
  logTextureRecovery(sweep_.store());
}

void StoreTextureSink::add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
                           const std::vector<capture::AmbientTerm>& ambient) {
  sweep_.add(frame, outcome, ambient);
}

capture::RunTextureFrames StoreTextureSink::run() const {
  const btf::TextureRun run = sweep_.run();
  return {run.fromSequence, run.toSequence};
}

control::TextureProgressView StoreTextureSink::status() const {
  const btf::TextureStore& store = sweep_.store();
  control::TextureProgressView view;
  view.directory = store.directory().string();
  view.resolution = store.layout().resolution;
  view.binsFilled = store.filledBins(sweep_.slice());
  view.framesStored = store.frameCount(sweep_.slice());
  view.sessionFramesStored = store.frameCount();
  view.storedMb = static_cast<double>(store.storedBytes()) / 1e6;
  view.damagedFramesRemoved = store.recovery().droppedFiles.size();
  return view;
}

}  // namespace slicecap::rig
