// The texture store's sweep runs: a run's frames set aside when it is refused, and the frames of
// earlier runs it replaced held until it is judged, so a refused run costs no earlier frame.
#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <system_error>

#include "slicecap/btf/texture_store.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::btf {

namespace fs = std::filesystem;

void TextureStore::requireMend() const {
  if (access_ != StoreAccess::Mend)
    throw std::logic_error("texture store: " + directory_.string() + " was opened read-only");
}

fs::path TextureStore::heldFolder(const SliceId& slice, std::uint64_t runStart) const {
  char run[24];
  std::snprintf(run, sizeof run, "%08llu", static_cast<unsigned long long>(runStart));
  return directory_ / (folderName(slice) + io::kHeldSuffix) / run;
}

std::uint64_t TextureStore::beginRun(const SliceId& slice) {
  requireMend();
  // An earlier run left unjudged keeps its held frames on disk: settleRuns decides them.
  runStart_[slice] = nextSequence_;
  return nextSequence_;
}

void TextureStore::keepRun(const SliceId& slice) {
  requireMend();
  const auto run = runStart_.find(slice);
  if (run == runStart_.end()) return;
  io::discardFolderDurably(heldFolder(slice, run->second));
  runStart_.erase(run);
}

std::size_t TextureStore::setAside(const SliceId& slice, std::uint64_t fromSequence,
                                   std::uint64_t toSequence) {
  requireMend();
  // The run is judged refused before anything can fail: were a move to throw with the run still
  // open, a later keepRun (the camera stopping) would delete the frames it replaced, which are
  // then the only copies of an earlier run's good frames. They stay held for settleRuns.
  if (const auto run = runStart_.find(slice); run != runStart_.end() && run->second == fromSequence)
    runStart_.erase(run);
  const TextureRun run{slice, fromSequence, toSequence};
  const auto inRun = [&](const Entry& e) { return run.holds(slice, e.sequence); };
  std::vector<fs::path> files;
  if (const auto found = index_.find(slice); found != index_.end())
    for (const std::vector<Entry>& bin : found->second)
      for (const Entry& e : bin)
        if (inRun(e)) files.push_back(e.file);
  // The index follows the disk: the frames leave it once they are moved (or if a move fails,
  // once they may be: a frame read from the wrong folder is worse than one left out).
  const auto forget = [&] {
    if (const auto found = index_.find(slice); found != index_.end())
      for (std::vector<Entry>& bin : found->second) std::erase_if(bin, inRun);
  };
  try {
    io::moveFilesDurably(files, directory_ / (folderName(slice) + io::kSetAsideSuffix));
  } catch (const io::IoError&) {
    forget();
    throw;
  }
  forget();
  // Only once the run's frames are out: the frames they replaced take their places again.
  restoreHeld(slice, fromSequence);
  return files.size();
}

void TextureStore::restoreHeld(const SliceId& slice, std::uint64_t runStart) {
  const fs::path held = heldFolder(slice, runStart);
  std::error_code error;
  if (!fs::is_directory(held, error)) return;
  const std::string name = folderName(slice);
  std::vector<StoredFrame> found;
  findFramesIn(held, name, found, error);
  if (error) throw io::IoError(held.string() + ": cannot list: " + error.message());
  std::vector<fs::path> files;
  for (StoredFrame& f : found) {
    files.push_back(f.entry.file);
    f.entry.file = directory_ / name / f.entry.file.filename();
  }
  io::createFoldersDurably(directory_ / name);
  io::moveFilesDurably(files, directory_ / name);
  // Back in the slice's folder: its bins are rebuilt in stored order, the keep rule as on opening
  // (the held frames were the bins' before the run, so they fit again).
  if (const auto kept = index_.find(slice); kept != index_.end()) {
    for (const std::vector<Entry>& bin : kept->second)
      for (const Entry& e : bin) found.push_back({slice, e});
    index_.erase(kept);
  }
  indexInStoredOrder(found);
  io::discardFolderDurably(held);
}

void TextureStore::numberPast(const std::vector<TextureRun>& refused) {
  for (const TextureRun& run : refused)
    if (run.toSequence != UINT64_MAX) nextSequence_ = std::max(nextSequence_, run.toSequence);
}

void TextureStore::leaveOutRefused(const std::vector<TextureRun>& refused,
                                   std::vector<StoredFrame>& found) {
  std::map<SliceId, std::vector<fs::path>> moved;
  std::erase_if(found, [&](const StoredFrame& f) {
    const bool inRefused = std::any_of(refused.begin(), refused.end(), [&](const TextureRun& r) {
      return r.holds(f.slice, f.entry.sequence);
    });
    if (inRefused) moved[f.slice].push_back(f.entry.file);
    return inRefused;
  });
  if (access_ != StoreAccess::Mend) return;
  for (const auto& [slice, files] : moved) {
    try {
      io::moveFilesDurably(files, directory_ / (folderName(slice) + io::kSetAsideSuffix));
    } catch (const io::IoError&) {
      // Left where they are, read by no opening given the refusals; the next one tries again.
      ++recovery_.leftovers;
    }
  }
}

std::size_t TextureStore::settleRuns(const std::vector<TextureRun>& refused) {
  requireMend();
  numberPast(refused);  // first: nothing settled below may be numbered inside a refused range
  std::size_t setAsideFrames = 0;
  for (const TextureRun& run : refused)
    setAsideFrames += setAside(run.slice, run.fromSequence, run.toSequence);
  // What is still held, no refusal names: its run was kept (or cut off by a crash, as good as
  // kept), and the frames that replaced these stand.
  std::error_code error;
  std::vector<fs::path> held;
  for (const fs::directory_entry& folder : fs::directory_iterator(directory_, error))
    if (folder.path().extension() == io::kHeldSuffix) held.push_back(folder.path());
  if (error) throw io::IoError(directory_.string() + ": cannot list: " + error.message());
  for (const fs::path& folder : held) io::discardFolderDurably(folder);
  return setAsideFrames;
}

}  // namespace slicecap::btf
