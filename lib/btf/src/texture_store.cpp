// The texture store: one atomically written file per kept frame, an in-memory index, the bins'
// keep rule re-applied on opening.
#include "slicecap/btf/texture_store.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "slicecap/btf/btf_error.hpp"
#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/io/target_json.hpp"
#include "texture_frame_file.hpp"
#include "texture_manifest.hpp"

namespace slicecap::btf {
namespace {

namespace fs = std::filesystem;
using namespace frame_file;
using namespace manifest;

void removeQuietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove_all(path, ignored);
}

}  // namespace

TextureStore::TextureStore(fs::path directory, TextureStoreLayout layout, StoreAccess access)
    : directory_(std::move(directory)), layout_(layout), access_(access) {}

TextureStore TextureStore::openOrCreate(const fs::path& directory,
                                        const TextureStoreLayout& layout,
                                        const std::vector<TextureRun>& refused) {
  checkLayout(layout);
  const fs::path manifest = directory / kTextureStoreManifest;
  if (!fs::exists(manifest)) {
    io::createFoldersDurably(directory);
    io::writeFileAtomically(manifest, layoutJson(layout).dump(2) + "\n");
  }
  TextureStore store = open(directory, StoreAccess::Mend, refused);
  const TextureStoreLayout& found = store.layout();
  const auto describe = [](const TextureStoreLayout& l) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "%d texels across, %d frames a bin, window x %g..%g y %g..%g mm", l.resolution,
                  l.framesPerBin, l.windowMm.xMinMm, l.windowMm.xMaxMm, l.windowMm.yMinMm,
                  l.windowMm.yMaxMm);
    return std::string(text);
  };
  if (found.resolution != layout.resolution || !(found.windowMm == layout.windowMm) ||
      found.framesPerBin != layout.framesPerBin)
    throw io::IoError(manifest.string() + ": this session's texture has " + describe(found) +
                      "; asked now: " + describe(layout) +
                      " (one session has one texture: change the configuration or target back, "
                      "or start a new session)");
  return store;
}

TextureStore TextureStore::open(const fs::path& directory, StoreAccess access,
                                const std::vector<TextureRun>& refused) {
  const fs::path manifest = directory / kTextureStoreManifest;
  if (!fs::exists(manifest))
    throw io::IoError(directory.string() + ": not a texture store (no " + kTextureStoreManifest +
                      ")");
  TextureStoreLayout layout = readLayout(manifest);
  try {
    checkLayout(layout);
  } catch (const BtfError& e) {
    throw io::IoError(manifest.string() + ": " + e.what());
  }
  TextureStore store(directory, layout, access);
  store.load(refused);
  return store;
}

void TextureStore::load(const std::vector<TextureRun>& refused) {
  numberPast(refused);
  std::vector<StoredFrame> found;
  std::error_code error;
  for (const fs::directory_entry& folder : fs::directory_iterator(directory_, error)) {
    if (!folder.is_directory()) {
      if (folder.path().extension() == ".tmp") setAsideLeftover(folder.path());
      continue;
    }
    const std::string name = folder.path().filename().string();
    if (name.find(io::kDiscardedSuffix) != std::string::npos) {  // a redo cut off half-way
      setAsideLeftover(folder.path());
      continue;
    }
    // A refused sweep run's frames (setAside): kept, never read; their sequence numbers still
    // count, so a later run's frame never takes (and a later refusal never overwrites) a name.
    if (folder.path().extension() == io::kSetAsideSuffix) {
      noteSequencesIn(folder.path());
      continue;
    }
    // Frames an unjudged run replaced (one folder per run): not read until the run is judged
    // (settleRuns); their numbers count too.
    if (folder.path().extension() == io::kHeldSuffix) {
      for (const fs::directory_entry& run : fs::directory_iterator(folder.path(), error))
        if (run.is_directory()) noteSequencesIn(run.path());
      if (error) break;
      continue;
    }
    findFramesIn(folder.path(), name, found, error);
    if (error) break;
  }
  if (error) throw io::IoError(directory_.string() + ": cannot list: " + error.message());
  // Before the keep rule: a refused run's frame left here (its set-aside failed or a crash cut
  // it off) must not take a bin slot and make the rule drop a kept run's frame.
  leaveOutRefused(refused, found);
  indexInStoredOrder(found);
}

void TextureStore::noteSequencesIn(const fs::path& folder) {
  std::error_code error;
  for (const fs::directory_entry& file : fs::directory_iterator(folder, error)) {
    if (file.path().extension() != kFrameExtension) continue;
    try {
      nextSequence_ = std::max(nextSequence_,
                               readFrameHeader(file.path(), layout_.resolution).sequence + 1);
    } catch (const BadFrame&) {
      // Not read anyway: a set-aside frame that cannot be read names no sequence.
    }
  }
}

void TextureStore::setAsideLeftover(const fs::path& path) {
  // A leftover is removed when mending, else just not read.
  if (access_ == StoreAccess::Mend) removeQuietly(path);
  ++recovery_.leftovers;
}

void TextureStore::findFramesIn(const fs::path& folder, const std::string& name,
                                std::vector<StoredFrame>& found, std::error_code& error) {
  for (const fs::directory_entry& file : fs::directory_iterator(folder, error)) {
    if (file.path().extension() == ".tmp") {  // a write cut off (or, read-only, under way)
      setAsideLeftover(file.path());
      continue;
    }
    if (file.path().extension() != kFrameExtension) continue;
    try {
      const FrameHeader header = readFrameHeader(file.path(), layout_.resolution);
      const SliceId slice{static_cast<SliceKind>(header.kind),
                          {header.thetaIDeg, header.thetaVDeg}};
      if (folderName(slice) != name)
        throw BadFrame(file.path().string() + ": a frame of " + folderName(slice) +
                       " in the folder of another slice");
      found.push_back({slice, {header.sliceParameterDeg, header.sequence, file.path()}});
    } catch (const BadFrame& e) {
      recovery_.droppedFiles.push_back(e.what());
      if (access_ == StoreAccess::Mend) removeQuietly(file.path());
    }
  }
}

void TextureStore::indexInStoredOrder(std::vector<StoredFrame>& found) {
  // In the order they were stored, through the keep rule: a crash between storing a frame and
  // deleting the one it replaced leaves both; the rule drops the replaced one again.
  std::sort(found.begin(), found.end(), [](const StoredFrame& a, const StoredFrame& b) {
    return a.entry.sequence < b.entry.sequence;
  });
  for (StoredFrame& f : found) {
    nextSequence_ = std::max(nextSequence_, f.entry.sequence + 1);
    const auto where = placeOf(f.slice, f.entry.parameterDeg);
    if (!where) {
      setAsideLeftover(f.entry.file);
      continue;
    }
    std::vector<Entry>& bin = indexFor(f.slice)[static_cast<std::size_t>(where->first)];
    if (where->second < bin.size()) {  // it replaces a frame whose deletion a crash cut off
      setAsideLeftover(bin[where->second].file);
      bin[where->second] = std::move(f.entry);
      continue;
    }
    bin.push_back(std::move(f.entry));
  }
}

TextureStore::SliceIndex& TextureStore::indexFor(const SliceId& slice) {
  SliceIndex& bins = index_[slice];
  if (bins.empty()) bins.resize(static_cast<std::size_t>(360.0 / kBinWidthDeg));
  return bins;
}

std::optional<std::pair<int, std::size_t>> TextureStore::placeOf(const SliceId& slice,
                                                                 double parameterDeg) const {
  const capture::AzimuthBins bins(slice.kind, kBinWidthDeg);
  const int bin = bins.binOf(parameterDeg);
  std::vector<double> kept;
  if (const auto found = index_.find(slice); found != index_.end())
    for (const Entry& e : found->second[static_cast<std::size_t>(bin)])
      kept.push_back(e.parameterDeg);
  const std::optional<std::size_t> slot =
      keepSlot(kept, parameterDeg, bin * kBinWidthDeg, layout_.framesPerBin);
  if (!slot) return std::nullopt;
  return std::make_pair(bin, *slot);
}

void TextureStore::place(const SliceId& slice, Entry entry, int bin, std::size_t slot) {
  std::vector<Entry>& kept = indexFor(slice)[static_cast<std::size_t>(bin)];
  if (slot == kept.size()) {
    kept.push_back(std::move(entry));
    return;
  }
  const Entry& replaced = kept[slot];
  // A frame of an earlier run than the slice's unjudged one is held until that run is judged:
  // if it is refused, this frame goes back (nothing captured by a kept run is lost). Held before
  // the index changes: if it cannot be, the replacement is not stored (add throws).
  if (const auto run = runStart_.find(slice);
      run != runStart_.end() && replaced.sequence < run->second) {
    io::moveFilesDurably({replaced.file}, heldFolder(slice, run->second));
    kept[slot] = std::move(entry);
    return;
  }
  const fs::path file = replaced.file;
  kept[slot] = std::move(entry);
  std::error_code error;
  fs::remove(file, error);
  // Left behind, the replaced frame is dropped again by the keep rule when the store is opened.
}

bool TextureStore::wouldKeep(const SliceId& slice, double parameterDeg) const {
  return placeOf(slice, parameterDeg).has_value();
}

bool TextureStore::add(const SliceId& slice, const TextureFrame& frame) {
  requireMend();
  if (slice.kind != SliceKind::Axial && slice.kind != SliceKind::Diagonal)
    throw BtfError("texture store: only axial and diagonal slices have a texture");
  const std::size_t values = grid().texelCount() * 3;
  if (frame.texels.size() != values)
    throw BtfError("texture store: a frame of " + std::to_string(frame.texels.size()) +
                   " values, expected " + std::to_string(values));
  const auto where = placeOf(slice, frame.sliceParameterDeg);
  if (!where) return false;
  const fs::path folder = directory_ / folderName(slice);
  io::createFoldersDurably(folder);
  const std::uint64_t sequence = nextSequence_++;
  char name[40];
  std::snprintf(name, sizeof name, "b%02d-%08llu%s", where->first,
                static_cast<unsigned long long>(sequence), kFrameExtension);
  const fs::path file = folder / name;
  io::writeFileAtomically(file, encodeFrame(slice, layout_.resolution, sequence, frame));
  try {
    place(slice, {frame.sliceParameterDeg, sequence, file}, where->first, where->second);
  } catch (const io::IoError&) {
    removeQuietly(file);  // the frame it would replace could not be held: that one stays
    throw;
  }
  return true;
}

void TextureStore::discard(const SliceId& slice) {
  requireMend();
  // The index follows the disk: if the folder cannot be discarded, its frames stay known. The
  // frames its runs held go first: they are the slice's too.
  io::discardFolderDurably(directory_ / (folderName(slice) + io::kHeldSuffix));
  io::discardFolderDurably(directory_ / folderName(slice));
  index_.erase(slice);
  runStart_.erase(slice);
}

std::vector<SliceId> TextureStore::slices() const {
  std::vector<SliceId> out;
  for (const auto& [slice, bins] : index_)
    if (frameCount(slice) > 0) out.push_back(slice);
  return out;
}

int TextureStore::filledBins(const SliceId& slice) const {
  const auto found = index_.find(slice);
  if (found == index_.end()) return 0;
  return static_cast<int>(std::count_if(found->second.begin(), found->second.end(),
                                        [](const auto& bin) { return !bin.empty(); }));
}

std::size_t TextureStore::frameCount(const SliceId& slice) const {
  const auto found = index_.find(slice);
  if (found == index_.end()) return 0;
  std::size_t count = 0;
  for (const auto& bin : found->second)
    count += bin.size();
  return count;
}

std::size_t TextureStore::frameCount() const {
  std::size_t count = 0;
  for (const auto& [slice, bins] : index_)
    count += frameCount(slice);
  return count;
}

std::size_t TextureStore::storedBytes() const {
  return frameCount() * frameFileBytes(layout_.resolution);
}

std::vector<SliceTexture> TextureStore::combine() const {
  std::vector<SliceTexture> out;
  const std::size_t texels = grid().texelCount();
  for (const SliceId& slice : slices()) {
    SliceTexture texture{slice, {}};
    for (const std::vector<Entry>& bin : index_.at(slice)) {
      std::vector<TextureFrame> frames;
      for (const Entry& e : bin)
        frames.push_back(readFrame(e.file, layout_.resolution));
      texture.bins.push_back(combineBinFrames(frames, texels));
    }
    out.push_back(std::move(texture));
  }
  return out;
}

}  // namespace slicecap::btf
