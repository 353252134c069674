// A capture session on disk: its description, and a journal of every accepted sample and sweep
// event.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/capture/window_cell_texture.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::capture {

/// \brief What a session is, as stored in <root>/<id>/session.json.
struct SessionInfo {
  std::string id;  ///< the folder's name (a copied or renamed session folder is its own session)
  std::string material;
  std::string createdUtc;  ///< ISO 8601, e.g. 2026-11-23T14:05:00Z
  /// Empty for a readable session; else why its session.json cannot be read (the folder still
  /// holds a journal, so it is listed as a damaged session, not left out).
  std::string damage;
  /// session.json's "format" as read (or written: a new session's 2, 4 from its first refusal).
  int format = 0;
};

/// \brief Something the journal could no longer tell for sure, and what opening the session did
/// about it: samples set aside (not counted, still in the journal) or lost.
struct JournalDamage {
  std::size_t line = 0;     ///< 1-based journal line; 0 for the journal as a whole
  std::string message;      ///< "<journal> line N: what was found; what it did to the samples"
  std::vector<SliceId> slicesSetAside;  ///< slices whose earlier samples no longer count
  std::size_t samplesSetAside = 0;      ///< samples set aside by this damage
  std::size_t samplesLost = 0;          ///< samples in records that could not be read
};

/// \brief The texture frames of a sweep run, as the session's texture store numbers them: from
/// the run's first to `to`, excluded (what a refusal sets aside there too).
struct RunTextureFrames {
  std::uint64_t from = 0;
  std::uint64_t to = 0;
};

/// \brief A sweep run refused for a decoding shown broken (the daemon's decoding watch): the
/// slice, why, and how many samples that set aside (the run's; in the journal, not counted);
/// with texture capture, the run's texture frames (the daemon sets them aside again whenever it
/// opens the session, so a crash before it moved them leaves none in the texture).
struct SweepRefusal {
  SliceId slice;
  std::string reason;
  std::size_t samplesSetAside = 0;
  std::optional<RunTextureFrames> textureFrames;
};

/// \brief One session directory: `session.json` (written atomically) and `journal` (one record per
/// accepted sample, sweep start/stop and redo, each on disk before the call returns). Opening
/// replays the journal, so a daemon killed mid-sweep resumes with every acknowledged sample. Errors
/// throw io::IoError naming the file.
class SessionStore {
 public:
  /// \brief Creates <root>/<id>; IoError if it exists or cannot be made. `id` must be a valid
  /// session id (CaptureError otherwise: it names a directory).
  static SessionStore create(const std::filesystem::path& root, const std::string& id,
                             const std::string& material);
  /// \brief Opens an existing session and replays its journal.
  static SessionStore open(const std::filesystem::path& root, const std::string& id);
  /// \brief Every session under root. A folder whose session.json cannot be read but that holds a
  /// journal is listed with SessionInfo::damage saying why; one with neither is no session.
  static std::vector<SessionInfo> list(const std::filesystem::path& root);
  /// \brief Deletes a session directory; IoError if it does not exist.
  static void remove(const std::filesystem::path& root, const std::string& id);

  const SessionInfo& info() const { return info_; }
  const std::filesystem::path& directory() const { return directory_; }
  const io::JournalRecovery& recovery() const { return recovery_; }
  /// \brief What replaying the journal could not tell for sure, in journal order: a damaged or
  /// unreadable record that may have changed which samples count (a redo) sets aside the earlier
  /// samples of its slice (of every slice when its slice cannot be read); a damaged sample
  /// record is skipped; missing records, a torn tail, a missing journal are said too.
  const std::vector<JournalDamage>& damage() const { return damage_; }
  /// \brief Samples of a slice that damage or refusals set aside: in the journal, but not counted.
  /// Like refusedCount, kept after a redo (the journal still holds them).
  std::size_t setAsideCount(const SliceId& slice) const;
  /// \brief Of setAsideCount, the samples refused sweep runs set aside (the rest: damage). Stays
  /// true after a redo, which forgets the refusals' reasons but not why samples were set aside.
  std::size_t refusedCount(const SliceId& slice) const;
  /// \brief True while a slice's counted samples are in doubt (damage set some aside); a redo of
  /// the slice ends the doubt.
  bool damaged(const SliceId& slice) const { return damagedSlices_.count(slice) > 0; }

  /// \brief Stores one accepted sample of a slice (durable when this returns), with its HDR
  /// reading and its window cells when it has them (replayed bit-identical; cells that would not
  /// replay are refused as an HDR reading is). Here and in recordSweepStarted and redo, a
  /// point slice (no sweep) is CaptureError, nothing written; so is an HDR reading that
  /// would not replay (not kHdrCellsPerSide^2 cells, a number not finite, a variance below 0, a
  /// level out of range), the message naming the frame and the field.
  void recordSample(const SliceId& slice, const FrameSample& sample);
  void recordSweepStarted(const SliceId& slice);
  void recordSweepStopped(const SliceId& slice);
  /// \brief Discards every sample of the slice so far (durable); later samples count again.
  /// Forgets the slice's refusals (their samples are discarded too).
  void redo(const SliceId& slice);
  /// \brief The number the next journal record gets: a sweep run beginning now has its samples
  /// from this record on (what refuse takes).
  std::uint64_t nextRecordNumber() const { return nextSequence_; }
  /// \brief Refuses a sweep run of the slice for `reason` (durable): the slice's samples in
  /// records numbered `firstRecord` or later (the run's: nextRecordNumber() as it began) stay in
  /// the journal but are set aside, so no table, fit or export uses them; the slice's earlier
  /// runs and later samples count. `textureFrames` (texture capture) are the run's texture
  /// frames, recorded with the refusal. A point slice is CaptureError, nothing written.
  void refuse(const SliceId& slice, const std::string& reason, std::uint64_t firstRecord,
              std::optional<RunTextureFrames> textureFrames = std::nullopt);
  /// \brief The refusals since each slice's last redo, in journal order.
  const std::vector<SweepRefusal>& refusals() const { return refusals_; }

  /// \brief The sweep that was started and not stopped (after a crash: the one to resume).
  std::optional<SliceId> activeSweep() const { return activeSweep_; }
  /// \brief The bins of a slice (empty bins if it has no samples).
  const AzimuthBins& bins(const SliceId& slice) const;
  std::size_t sampleCount() const;
  std::size_t sampleCount(const SliceId& slice) const;
  /// \brief Every slice combined bin by bin (AzimuthBins::combine), ready for reconstruction,
  /// with each slice's values from its window cells as cell samples (addSweepSlices) when its
  /// samples carry cells. With `verdicts`, each such slice's texture verdict (what
  /// addSweepSlices returns) goes into it, for the reports that say how its cells were read.
  SliceSet slices(std::map<SliceId, CellTexture>* verdicts = nullptr) const;

 private:
  SessionStore(std::filesystem::path directory, SessionInfo info, io::Journal journal);
  void replay(const std::vector<io::JournalLine>& lines);  // session_journal_replay.cpp
  // Whether the record is applied, after what its number says of records missing or repeated.
  bool acceptRecordNumber(const io::JournalLine& line, const std::optional<nlohmann::json>& j,
                          const std::string& where, std::uint64_t& expected);
  // An intact record this version cannot apply, and one whose checksum failed: by its remains.
  void judgeUnusableRecord(std::size_t line, const std::string& reason,
                           const std::optional<std::string>& type,
                           const std::optional<SliceId>& slice);
  void judgeDamagedRecord(std::size_t line, const std::string& where,
                          const std::optional<std::string>& type,
                          const std::optional<SliceId>& slice);
  void apply(const nlohmann::json& record, std::size_t line, std::uint64_t number);
  void setAside(std::size_t line, std::string what, std::optional<SliceId> slice);
  // An old (format 3) record without a first record refuses every counted sample of the slice.
  void applyRefusal(const SliceId& slice, std::string reason,
                    std::optional<std::uint64_t> firstRecord,
                    std::optional<RunTextureFrames> textureFrames);
  // A sample counted in its bins, from the record numbered `record`.
  void countSample(const SliceId& slice, const FrameSample& sample, std::uint64_t record);
  // Every counted sample of the slice gone from the bins (a redo, a set-aside).
  void uncountAll(const SliceId& slice);
  void forgetRefusals(const SliceId& slice);
  void append(nlohmann::json record);  // numbers it ("n") and makes it durable
  AzimuthBins& binsFor(const SliceId& slice);

  std::filesystem::path directory_;
  SessionInfo info_;
  io::Journal journal_;
  io::JournalRecovery recovery_;
  std::map<SliceId, AzimuthBins> bins_;
  std::optional<SliceId> activeSweep_;
  std::vector<JournalDamage> damage_;
  std::map<SliceId, std::size_t> setAside_;
  std::set<SliceId> damagedSlices_;
  std::vector<SweepRefusal> refusals_;
  std::map<SliceId, std::size_t> refusedAside_;
  // Each counted sample's record number and bin, in journal order (a refusal takes the latest).
  struct CountedSample {
    std::uint64_t record = 0;
    int bin = 0;
  };
  std::map<SliceId, std::vector<CountedSample>> counted_;
  std::uint64_t nextSequence_ = 1;  ///< the "n" of the next record: records count their lines
};

}  // namespace slicecap::capture
