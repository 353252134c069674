// Session directories: atomic description, replayed journal of samples and sweep events.
#include "slicecap/capture/session_store.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "journal_records.hpp"
#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/core/session_id.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::capture {
namespace {

using nlohmann::json;
using namespace journal_records;
// 2: sample records may hold the window's cells ("cells"); a version that ignores them would
// read the session's samples as window centres alone. Format 1 sessions (no cells) still open.
// 3: the journal may hold a `refuse` record. A version before it reads that record as damage and
// sets aside every slice's samples before it, not the refused slice's alone, so a session is
// marked 3 when its first refusal is written, and such a version refuses to open it, naming the
// file; a session without a refusal stays 2, readable by those versions.
// 4: a `refuse` record names the first record of the refused sweep run ("from"), and only that
// run's samples are set aside. A version reading 3 would set aside every sample of the slice
// before it (earlier good runs too), so a session is marked 4 with its first such record. A
// format 3 record (no "from") still reads as it was written: every counted sample of its slice.
// A `refuse` record may also name the run's texture frames ("texture_from", "texture_to"): no
// format step, as a version that ignores them reads the samples alike (it only does not set the
// frames aside again on opening), and a record without them reads as before.
constexpr int kFormatVersion = 4;
constexpr int kNewSessionFormatVersion = 2;
constexpr int kOldestFormatVersion = 1;
constexpr int kRunRefusalFormatVersion = 4;

void writeDescription(const std::filesystem::path& directory, const SessionInfo& info, int format) {
  io::writeFileAtomically(directory / "session.json",
                          json{{"format", format},
                               {"id", info.id},
                               {"material", info.material},
                               {"created", info.createdUtc}}
                              .dump(2, ' ', false, json::error_handler_t::replace));
}

// A sweep is of an axial or a diagonal slice: a point "slice" has no azimuth bins, and a journal
// record of it would not replay (the session would no longer open). Refused before anything is
// written.
void requireSweepSlice(const SliceId& slice) {
  if (slice.kind == SliceKind::Point)
    throw CaptureError("slice " + toString(slice) +
                       ": a sweep is of an axial or a diagonal slice");
}

std::string utcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// The description of the session in `directory`. Its id is the folder's name, whatever id the
// file was written with: a copied or renamed folder is a session of its own, and everything
// that finds a session by id (open, remove, the daemon's current session) finds it there.
SessionInfo readInfo(const std::filesystem::path& directory) {
  const std::filesystem::path file = directory / "session.json";
  errno = 0;
  std::ifstream in(file);
  if (!in)
    throw io::IoError(file.string() + ": cannot open session description" +
                      (errno ? std::string(" (") + std::strerror(errno) + ")" : std::string()));
  const json j = io::parseJson(std::string(std::istreambuf_iterator<char>(in), {}), file.string());
  if (!j.is_object()) throw io::IoError(file.string() + ": not a JSON object");
  try {
    const json& format = j.at("format");
    if (!format.is_number_integer() || format.get<std::int64_t>() < kOldestFormatVersion ||
        format.get<std::int64_t>() > kFormatVersion) {
      throw io::IoError(file.string() + ": field \"format\" is " + format.dump() + ", expected " +
                        std::to_string(kOldestFormatVersion) + " to " +
                        std::to_string(kFormatVersion));
    }
    static_cast<void>(j.at("id").get<std::string>());  // required: else not a session
    return {directory.filename().string(),
            j.at("material").get<std::string>(),
            j.at("created").get<std::string>(),
            {},
            static_cast<int>(format.get<std::int64_t>())};
  } catch (const json::exception& e) {
    throw io::IoError(file.string() + ": " + e.what());
  }
}

}  // namespace

SessionStore::SessionStore(std::filesystem::path directory, SessionInfo info, io::Journal journal)
    : directory_(std::move(directory)), info_(std::move(info)), journal_(std::move(journal)) {}

SessionStore SessionStore::create(const std::filesystem::path& root, const std::string& id,
                                  const std::string& material) {
  if (!isValidSessionId(id)) throw CaptureError("invalid session id '" + id + "'");
  const std::filesystem::path directory = root / id;
  std::error_code error;
  std::filesystem::create_directories(root, error);
  if (!std::filesystem::create_directory(directory, error)) {
    throw io::IoError(directory.string() +
                      (error ? ": cannot create: " + error.message() : ": session exists already"));
  }
  // The journal before the description: a session.json without its journal then always means
  // the journal was lost, which opening says.
  io::Journal journal = io::Journal::open(directory / kJournal, nullptr);
  SessionInfo info{id, material, utcNow(), {}, kNewSessionFormatVersion};
  writeDescription(directory, info, kNewSessionFormatVersion);
  return SessionStore(directory, std::move(info), std::move(journal));
}

SessionStore SessionStore::open(const std::filesystem::path& root, const std::string& id) {
  if (!isValidSessionId(id)) throw CaptureError("invalid session id '" + id + "'");
  const std::filesystem::path directory = root / id;
  if (!std::filesystem::is_directory(directory))
    throw io::IoError(directory.string() + ": no such session");
  SessionInfo info = readInfo(directory);
  const std::filesystem::path journalPath = directory / kJournal;
  const std::filesystem::path missingMark = directory / kJournalMissing;
  std::error_code error;
  if (!std::filesystem::exists(journalPath, error) && !error &&
      !std::filesystem::exists(missingMark, error))
    io::writeFileAtomically(
        missingMark, "the journal was missing when the session was opened on " + utcNow() + "\n");
  std::vector<io::JournalLine> lines;
  io::JournalRecovery recovery;
  io::Journal journal = io::Journal::openLines(journalPath, &lines, &recovery);
  SessionStore store(directory, std::move(info), std::move(journal));
  store.recovery_ = recovery;
  // Said for as long as the marks are there: a person who has read them may delete them.
  if (std::filesystem::exists(missingMark, error))
    store.damage_.push_back({0,
                             journalPath.string() +
                                 ": was missing (deleted?) when the session was opened: every "
                                 "sample recorded before is lost; a new journal was started (" +
                                 missingMark.filename().string() + " says when)",
                             {},
                             0,
                             0});
  store.replay(lines);
  const std::filesystem::path torn = io::tornTailFile(journalPath);
  if (std::filesystem::exists(torn, error))
    store.damage_.push_back(
        {0,
         journalPath.string() + ": ended in an unfinished record (" +
             std::to_string(std::filesystem::file_size(torn, error)) +
             " bytes: a write cut short by a crash, never acknowledged); it was cut off and kept "
             "in " +
             torn.string(),
         {},
         0,
         0});
  return store;
}

std::vector<SessionInfo> SessionStore::list(const std::filesystem::path& root) {
  std::vector<SessionInfo> sessions;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(root, error)) {
    if (!entry.is_directory() || !isValidSessionId(entry.path().filename().string())) continue;
    try {
      sessions.push_back(readInfo(entry.path()));
    } catch (const io::IoError& unreadable) {
      // A half-created (an empty journal, no description) or foreign folder is not a session;
      // one whose description is damaged, or whose journal holds records, is: listed as such.
      std::error_code ignored;
      const auto journalBytes = std::filesystem::file_size(entry.path() / kJournal, ignored);
      const bool hasRecords = !ignored && journalBytes > 0;
      if (hasRecords || std::filesystem::exists(entry.path() / "session.json", ignored))
        sessions.push_back({entry.path().filename().string(), "", "", unreadable.what()});
    }
  }
  std::sort(sessions.begin(), sessions.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  return sessions;
}

void SessionStore::remove(const std::filesystem::path& root, const std::string& id) {
  if (!isValidSessionId(id)) throw CaptureError("invalid session id '" + id + "'");
  const std::filesystem::path directory = root / id;
  if (!std::filesystem::is_directory(directory))
    throw io::IoError(directory.string() + ": no such session");
  std::filesystem::remove_all(directory);
}

AzimuthBins& SessionStore::binsFor(const SliceId& slice) {
  return bins_.try_emplace(slice, slice.kind).first->second;
}

const AzimuthBins& SessionStore::bins(const SliceId& slice) const {
  static const AzimuthBins emptyAxial(SliceKind::Axial), emptyDiagonal(SliceKind::Diagonal);
  auto it = bins_.find(slice);
  if (it != bins_.end()) return it->second;
  return slice.kind == SliceKind::Axial ? emptyAxial : emptyDiagonal;
}

std::size_t SessionStore::setAsideCount(const SliceId& slice) const {
  const auto it = setAside_.find(slice);
  return it == setAside_.end() ? 0 : it->second;
}

std::size_t SessionStore::refusedCount(const SliceId& slice) const {
  const auto it = refusedAside_.find(slice);
  return it == refusedAside_.end() ? 0 : it->second;
}

void SessionStore::countSample(const SliceId& slice, const FrameSample& sample,
                               std::uint64_t record) {
  AzimuthBins& bins = binsFor(slice);
  bins.add(sample);
  counted_[slice].push_back({record, bins.binOf(sample)});
}

void SessionStore::uncountAll(const SliceId& slice) {
  binsFor(slice).clear();
  counted_.erase(slice);
}

void SessionStore::append(json record) {
  record["n"] = nextSequence_;
  journal_.append(record.dump());
  ++nextSequence_;  // only once it is on disk: a failed append is rolled back
}

void SessionStore::recordSample(const SliceId& slice, const FrameSample& s) {
  requireSweepSlice(slice);
  json record{{"t", "sample"},
              {"slice", sliceJson(slice)},
              {"ts", s.timestampUs},
              {"frame", s.frameIndex},
              {"light", {s.light.thetaDeg, s.light.phiDeg}},
              {"view", {s.view.thetaDeg, s.view.phiDeg}},
              {"rgb", {s.value.r(), s.value.g(), s.value.b()}}};
  // An HDR sample's reading goes with it: the bins merge the exposures per cell after a restart
  // too. Checked before it is written, as replay checks it: a reading that would not replay
  // (a NaN is written as null) would be a sample counted now and lost on the next open.
  if (s.hdr) {
    try {
      requireValidHdr(*s.hdr);
    } catch (const CaptureError& e) {
      throw CaptureError("sample of frame " + std::to_string(s.frameIndex) + " of " +
                         toString(slice) + ": " + e.what() + "; nothing written");
    }
    record["hdr"] = hdrJson(*s.hdr);
  }
  if (s.cells) {
    try {
      requireValidCells(*s.cells);
    } catch (const CaptureError& e) {
      throw CaptureError("sample of frame " + std::to_string(s.frameIndex) + " of " +
                         toString(slice) + ": " + e.what() + "; nothing written");
    }
    record["cells"] = cellsJson(*s.cells);
  }
  const std::uint64_t number = nextSequence_;
  append(std::move(record));
  // durable first: only then does the sample count
  countSample(slice, s, number);
}

void SessionStore::recordSweepStarted(const SliceId& slice) {
  requireSweepSlice(slice);
  append(json{{"t", "start"}, {"slice", sliceJson(slice)}});
  activeSweep_ = slice;
}

void SessionStore::recordSweepStopped(const SliceId& slice) {
  append(json{{"t", "stop"}, {"slice", sliceJson(slice)}});
  if (activeSweep_ == slice) activeSweep_.reset();
}

void SessionStore::redo(const SliceId& slice) {
  requireSweepSlice(slice);
  append(json{{"t", "redo"}, {"slice", sliceJson(slice)}});
  uncountAll(slice);
  damagedSlices_.erase(slice);
  forgetRefusals(slice);
}

void SessionStore::refuse(const SliceId& slice, const std::string& reason,
                          std::uint64_t firstRecord,
                          std::optional<RunTextureFrames> textureFrames) {
  requireSweepSlice(slice);
  // The description first: a session marked 4 without the record is still read right.
  if (info_.format < kRunRefusalFormatVersion) {
    writeDescription(directory_, info_, kRunRefusalFormatVersion);
    info_.format = kRunRefusalFormatVersion;
  }
  json record{{"t", "refuse"}, {"slice", sliceJson(slice)}, {"reason", reason},
              {"from", firstRecord}};
  if (textureFrames) {
    record["texture_from"] = textureFrames->from;
    record["texture_to"] = textureFrames->to;
  }
  append(std::move(record));
  applyRefusal(slice, reason, firstRecord, textureFrames);
}

void SessionStore::applyRefusal(const SliceId& slice, std::string reason,
                                std::optional<std::uint64_t> firstRecord,
                                std::optional<RunTextureFrames> textureFrames) {
  // The run's samples are the slice's latest (records are numbered in journal order): each is
  // the latest of its bin when it is taken out, newest first.
  std::vector<CountedSample>& counted = counted_[slice];
  std::size_t refused = 0;
  while (!counted.empty() && (!firstRecord || counted.back().record >= *firstRecord)) {
    binsFor(slice).removeLatest(counted.back().bin);
    counted.pop_back();
    ++refused;
  }
  setAside_[slice] += refused;
  refusedAside_[slice] += refused;
  refusals_.push_back({slice, std::move(reason), refused, textureFrames});
}

void SessionStore::forgetRefusals(const SliceId& slice) {
  std::erase_if(refusals_, [&](const SweepRefusal& r) { return r.slice == slice; });
}

std::size_t SessionStore::sampleCount() const {
  std::size_t count = 0;
  for (const auto& [slice, bins] : bins_)
    count += sampleCount(slice);
  return count;
}

std::size_t SessionStore::sampleCount(const SliceId& slice) const {
  const AzimuthBins& b = bins(slice);
  std::size_t count = 0;
  for (int k = 0; k < b.binCount(); ++k)
    count += b.samplesIn(k).size();
  return count;
}

SliceSet SessionStore::slices(std::map<SliceId, CellTexture>* verdicts) const {
  SliceSet set;
  for (const auto& [slice, bins] : bins_) {
    CellTexture texture = addSweepSlices(set, slice, bins);
    if (verdicts && texture.framesUsed > 0) (*verdicts)[slice] = std::move(texture);
  }
  return set;
}

}  // namespace slicecap::capture
