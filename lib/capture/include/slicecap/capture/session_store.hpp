// A capture session on disk: its description, and a journal of every accepted sample and sweep
// event.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::capture {

/// \brief What a session is, as stored in <root>/<id>/session.json.
struct SessionInfo {
  std::string id;  ///< the folder's name (a copied or renamed session folder is its own session)
  std::string material;
  std::string createdUtc;  ///< ISO 8601, e.g. 2026-11-23T14:05:00Z
};

/// \brief One session directory: `session.json` (written atomically) and `journal` (one record per
/// accepted sample, sweep start/stop and redo, each on disk before the call returns). Opening
/// replays the journal, so a daemon killed mid-sweep resumes with every acknowledged sample. Errors
/// throw io::IoError naming the file.
class SessionStore {
 public:
  /// \brief Creates <root>/<id>; IoError if it exists or cannot be made. `id` must be a valid
  /// session id (std::invalid_argument otherwise: it names a directory).
  static SessionStore create(const std::filesystem::path& root, const std::string& id,
                             const std::string& material);
  /// \brief Opens an existing session and replays its journal.
  static SessionStore open(const std::filesystem::path& root, const std::string& id);
  /// \brief Every session under root (sessions whose session.json cannot be read are skipped).
  static std::vector<SessionInfo> list(const std::filesystem::path& root);
  /// \brief Deletes a session directory; IoError if it does not exist.
  static void remove(const std::filesystem::path& root, const std::string& id);

  const SessionInfo& info() const { return info_; }
  const std::filesystem::path& directory() const { return directory_; }
  const io::JournalRecovery& recovery() const { return recovery_; }

  /// \brief Stores one accepted sample of a slice (durable when this returns). Here and in
  /// recordSweepStarted and redo, a point slice (no sweep) is std::invalid_argument, nothing
  /// written.
  void recordSample(const SliceId& slice, const FrameSample& sample);
  void recordSweepStarted(const SliceId& slice);
  void recordSweepStopped(const SliceId& slice);
  /// \brief Discards every sample of the slice so far (durable); later samples count again.
  void redo(const SliceId& slice);

  /// \brief The sweep that was started and not stopped (after a crash: the one to resume).
  std::optional<SliceId> activeSweep() const { return activeSweep_; }
  /// \brief The bins of a slice (empty bins if it has no samples).
  const AzimuthBins& bins(const SliceId& slice) const;
  std::size_t sampleCount() const;
  std::size_t sampleCount(const SliceId& slice) const;
  /// \brief Every slice combined bin by bin (AzimuthBins::combine), ready for reconstruction.
  SliceSet slices() const;

 private:
  SessionStore(std::filesystem::path directory, SessionInfo info, io::Journal journal);
  void apply(const std::string& record, std::size_t recordNumber);
  AzimuthBins& binsFor(const SliceId& slice);

  std::filesystem::path directory_;
  SessionInfo info_;
  io::Journal journal_;
  io::JournalRecovery recovery_;
  std::map<SliceId, AzimuthBins> bins_;
  std::optional<SliceId> activeSweep_;
};

/// \brief True for 1-64 characters of [a-z0-9_-], the first a letter or digit.
bool isValidSessionId(const std::string& id);

}  // namespace slicecap::capture
