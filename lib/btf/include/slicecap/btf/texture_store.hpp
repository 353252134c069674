// A session's texture on disk, as the daemon captures it (docs/btf-format.md, "Texture store"):
// per slice and azimuth bin the kept frames' rectified texels, each frame in its own file written
// atomically. Bounded however long the sweeps: at most bins x framesPerBin frames a slice.
#pragma once

#include <cstdint>
#include <optional>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include "slicecap/btf/slice_texture.hpp"
#include "slicecap/btf/texture_grid.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::btf {

/// \brief What a store holds, fixed when it is created (texture.json).
struct TextureStoreLayout {
  int resolution = 128;     ///< texels across the window
  vision::RectMm windowMm;  ///< the target's window the texture covers
  int framesPerBin = 5;     ///< frames a bin keeps, those nearest its centre
};

/// \brief How a store is opened: the daemon's store mends what a crash left; a reader (`slicecap
/// btf` on an export) changes nothing, as the folder may still be written by a daemon.
enum class StoreAccess { Mend, ReadOnly };

/// \brief A sweep run's frames in a store: those of `slice` numbered `fromSequence` to
/// `toSequence` - 1 (what the journal's refusal of the run records, TextureStore::setAside).
struct TextureRun {
  SliceId slice;
  std::uint64_t fromSequence = 0;
  std::uint64_t toSequence = 0;
  /// \brief Whether the frame numbered `sequence` of `frameSlice` is one of the run's.
  bool holds(const SliceId& frameSlice, std::uint64_t sequence) const {
    return frameSlice == slice && sequence >= fromSequence && sequence < toSequence;
  }
};

/// \brief What opening a store found (and, mending, removed): what a cut-off write, a crash
/// between a write and an eviction, or a damaged disk left behind.
struct TextureStoreRecovery {
  /// \brief Frame files whose content is wrong (torn, damaged header, another store's): not read.
  std::vector<std::string> droppedFiles;
  /// \brief Temporaries, half-discarded slices, frames the keep rule had replaced: not read.
  std::size_t leftovers = 0;
};

/// \brief The texture of one session. Every kept frame is a file written atomically (temporary,
/// fsync, rename), so a killed daemon keeps every frame add() stored; a frame replaced by one
/// nearer its bin's centre is deleted after its replacement is on disk, unless it is of an
/// earlier sweep run than its replacement: then it is held until that run is judged (beginRun). Memory holds only the
/// index: texels are read back when the slices are combined. Texels are stored as half floats
/// (the BTF's own precision). Errors throw io::IoError naming the file.
class TextureStore {
 public:
  /// \brief Opens the store in `directory`, creating it with `layout` if there is none; an
  /// existing store with another resolution, window or frames per bin is an IoError (one session
  /// has one texture). BtfError for an invalid layout.
  static TextureStore openOrCreate(const std::filesystem::path& directory,
                                   const TextureStoreLayout& layout,
                                   const std::vector<TextureRun>& refused = {});
  /// \brief Opens an existing store. Mend (the daemon's) removes what a crash left (see
  /// TextureStoreRecovery); ReadOnly (`slicecap btf`) leaves every file alone and refuses add and
  /// discard (std::logic_error). A frame file that cannot be opened is an IoError naming it (it
  /// is not removed: the cause may pass). `refused`: the journal's refused runs, applied before
  /// the keep rule: their frames are never indexed (mending, they are moved aside as setAside
  /// does; one that cannot be stays, unread, for the next opening), so they never cost a kept
  /// frame its bin; and no frame stored from now on takes a number inside their ranges.
  static TextureStore open(const std::filesystem::path& directory,
                           StoreAccess access = StoreAccess::Mend,
                           const std::vector<TextureRun>& refused = {});

  const std::filesystem::path& directory() const { return directory_; }
  const TextureStoreLayout& layout() const { return layout_; }
  TextureGrid grid() const { return TextureGrid(layout_.resolution, layout_.windowMm); }
  const TextureStoreRecovery& recovery() const { return recovery_; }

  /// \brief Whether a frame of `slice` at this slice parameter would be kept: ask before
  /// rectifying a frame, as most frames of a long sweep are not kept.
  bool wouldKeep(const SliceId& slice, double parameterDeg) const;
  /// \brief Stores the frame if its bin keeps it (durable when this returns) and deletes the
  /// frame it replaces, or holds it (moved durably into `<slice folder>.held/<run>/`) if it is of
  /// an earlier run than the slice's run begun (beginRun); returns whether it was kept. BtfError
  /// for a frame of another texel count; IoError if it cannot be written or the replaced frame
  /// cannot be held (the frame is then not stored).
  bool add(const SliceId& slice, const TextureFrame& frame);
  /// \brief Deletes every frame of the slice (a redone sweep) and the frames its runs held,
  /// durably (io::discardFolderDurably); if it cannot, the frames stay and are still indexed
  /// (IoError).
  void discard(const SliceId& slice);
  /// \brief The sequence number the next stored frame gets: a sweep run beginning now stores its
  /// frames from this number on (what setAside takes).
  std::uint64_t nextSequence() const { return nextSequence_; }
  /// \brief A sweep run of the slice begins: the frames stored from now on are the run's (until
  /// the next beginRun), and a frame of an earlier run one of them replaces is held, not deleted,
  /// until the run is judged: keepRun deletes them, setAside of the run puts them back. Returns
  /// the run's first sequence number (what setAside takes).
  std::uint64_t beginRun(const SliceId& slice);
  /// \brief The slice's run (beginRun) is kept: the frames it replaced are deleted durably.
  /// IoError if they cannot be (they stay held, never read, and settleRuns drops them).
  void keepRun(const SliceId& slice);
  /// \brief Sets aside the slice's frames numbered `fromSequence` to `toSequence` - 1 (a refused
  /// sweep run's): moved durably into the folder `<slice folder>` + io::kSetAsideSuffix beside
  /// the slice's, where no store reads them and no export copies them, and dropped from the
  /// index, so a later run fills their bins. The frames of earlier runs the run replaced (held
  /// for a run begun at `fromSequence`) go back into their bins, the keep rule re-applied in
  /// stored order. Idempotent: frames set aside already are not in the index. Returns how many
  /// frames were set aside; IoError if one cannot be moved (those moved before it are out of the
  /// index, the held frames are left held for settleRuns: the run counts as judged either way, so
  /// keepRun never deletes them).
  std::size_t setAside(const SliceId& slice, std::uint64_t fromSequence,
                       std::uint64_t toSequence = UINT64_MAX);
  /// \brief What the daemon does when it opens a session: sets aside every run its journal
  /// refused (setAside: a crash between the refusal and the move left their frames here), then
  /// deletes every frame still held, as no refusal names its run (a run a crash cut off before
  /// it was judged counts as kept). Returns the frames set aside; IoError as setAside, nothing
  /// held deleted then.
  std::size_t settleRuns(const std::vector<TextureRun>& refused);

  /// \brief The slices with at least one stored frame.
  std::vector<SliceId> slices() const;
  int filledBins(const SliceId& slice) const;
  std::size_t frameCount(const SliceId& slice) const;
  std::size_t frameCount() const;
  /// \brief Bytes of texel data on disk (index only in memory).
  std::size_t storedBytes() const;

  /// \brief Every stored slice's bins combined (combineBinFrames), in SliceId order: the input of
  /// reconstructBtf. Reads every frame file; one that became unreadable is an IoError naming it.
  std::vector<SliceTexture> combine() const;

 private:
  struct Entry {
    double parameterDeg = 0.0;
    std::uint64_t sequence = 0;
    std::filesystem::path file;
  };
  using SliceIndex = std::vector<std::vector<Entry>>;  // per bin
  struct StoredFrame {  // a frame file found when opening: its slice and index entry
    SliceId slice;
    Entry entry;
  };

  TextureStore(std::filesystem::path directory, TextureStoreLayout layout, StoreAccess access);
  void load(const std::vector<TextureRun>& refused);
  /// No frame stored from now on is numbered inside a refused run's range (a number a failed
  /// write used leaves the files short of the range's end).
  void numberPast(const std::vector<TextureRun>& refused);
  /// The found frames of refused runs out of `found` (and, mending, moved aside).
  void leaveOutRefused(const std::vector<TextureRun>& refused, std::vector<StoredFrame>& found);
  /// load's steps: a leftover (.tmp, a redo cut off) is counted, and removed when mending; a
  /// slice folder's frame files are listed; the frames found are indexed in stored order.
  void setAsideLeftover(const std::filesystem::path& path);
  void noteSequencesIn(const std::filesystem::path& folder);
  void findFramesIn(const std::filesystem::path& folder, const std::string& sliceFolder,
                    std::vector<StoredFrame>& found, std::error_code& error);
  void indexInStoredOrder(std::vector<StoredFrame>& found);
  SliceIndex& indexFor(const SliceId& slice);
  /// The bin and slot a frame would take (slot == bin size: appended), or none.
  std::optional<std::pair<int, std::size_t>> placeOf(const SliceId& slice,
                                                     double parameterDeg) const;
  void place(const SliceId& slice, Entry entry, int bin, std::size_t slot);
  void requireMend() const;
  /// Where the frames replaced by the slice's run begun at `runStart` are held.
  std::filesystem::path heldFolder(const SliceId& slice, std::uint64_t runStart) const;
  /// The frames held for the run begun at `runStart` back into the slice's folder and bins.
  void restoreHeld(const SliceId& slice, std::uint64_t runStart);

  std::filesystem::path directory_;
  TextureStoreLayout layout_;
  StoreAccess access_;
  TextureStoreRecovery recovery_;
  std::map<SliceId, SliceIndex> index_;
  std::map<SliceId, std::uint64_t> runStart_;  // the slices' runs begun and not yet judged
  std::uint64_t nextSequence_ = 1;
};

/// \brief The store's manifest file name.
inline constexpr const char* kTextureStoreManifest = "texture.json";

}  // namespace slicecap::btf
