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

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::capture {
namespace {

using nlohmann::json;
constexpr int kFormatVersion = 1;
constexpr const char* kJournal = "journal";
// Left in a session folder whose journal was missing when it was opened: the loss is said on
// every later open, not only the first.
constexpr const char* kJournalMissing = "journal.missing";

json sliceJson(const SliceId& s) {
  return {{"kind", toString(s.kind)},
          {"theta_i", s.elevations.thetaIDeg},
          {"theta_v", s.elevations.thetaVDeg}};
}

// A whole number in lo..hi. nlohmann's get<int>() of 1e300 is undefined behaviour and its
// get<std::uint64_t>() of -1 wraps round, so a damaged record would not be named.
template <typename T>
T wholeNumber(const json& parent, const std::string& key, T lo, T hi) {
  const json& value = parent.at(key);
  const auto within = [&](auto v) {
    return std::cmp_greater_equal(v, lo) && std::cmp_less_equal(v, hi);
  };
  if (value.is_number_unsigned() && within(value.get<std::uint64_t>()))
    return static_cast<T>(value.get<std::uint64_t>());
  if (value.is_number_integer() && !value.is_number_unsigned() && within(value.get<std::int64_t>()))
    return static_cast<T>(value.get<std::int64_t>());
  throw std::invalid_argument(key + ": expected a whole number in " + std::to_string(lo) + ".." +
                              std::to_string(hi) + ", got " + value.dump());
}

template <typename T>
T wholeNumber(const json& parent, const std::string& key) {
  return wholeNumber(parent, key, std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
}

SliceId sliceFrom(const json& j) {
  const auto kind = parseSliceKind(j.at("kind").get<std::string>());
  if (!kind) throw std::invalid_argument("unknown slice kind");
  return {*kind, {wholeNumber(j, "theta_i", 0, 89), wholeNumber(j, "theta_v", 0, 89)}};
}

// A sweep is of an axial or a diagonal slice: a point "slice" has no azimuth bins, and a journal
// record of it would not replay (the session would no longer open). Refused before anything is
// written.
void requireSweepSlice(const SliceId& slice) {
  if (slice.kind == SliceKind::Point)
    throw std::invalid_argument("slice " + toString(slice) +
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
    if (!j.at("format").is_number_integer() || j.at("format") != kFormatVersion) {
      throw io::IoError(file.string() + ": field \"format\" is " + j.at("format").dump() +
                        ", expected 1");
    }
    static_cast<void>(j.at("id").get<std::string>());  // required: else not a session
    return {directory.filename().string(), j.at("material").get<std::string>(),
            j.at("created").get<std::string>(), {}};
  } catch (const json::exception& e) {
    throw io::IoError(file.string() + ": " + e.what());
  }
}

}  // namespace

bool isValidSessionId(const std::string& id) {
  auto letterOrDigit = [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); };
  // Not starting with '-' or '_': an id is an argument of the CLI, where "-x" reads as an option.
  return !id.empty() && id.size() <= 64 && letterOrDigit(id.front()) &&
         std::all_of(id.begin(), id.end(),
                     [&](char c) { return letterOrDigit(c) || c == '_' || c == '-'; });
}

SessionStore::SessionStore(std::filesystem::path directory, SessionInfo info, io::Journal journal)
    : directory_(std::move(directory)), info_(std::move(info)), journal_(std::move(journal)) {}

SessionStore SessionStore::create(const std::filesystem::path& root, const std::string& id,
                                  const std::string& material) {
  if (!isValidSessionId(id)) throw std::invalid_argument("invalid session id '" + id + "'");
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
  SessionInfo info{id, material, utcNow(), {}};
  io::writeFileAtomically(directory / "session.json",
                          json{{"format", kFormatVersion},
                               {"id", id},
                               {"material", material},
                               {"created", info.createdUtc}}
                              .dump(2, ' ', false, json::error_handler_t::replace));
  return SessionStore(directory, std::move(info), std::move(journal));
}

SessionStore SessionStore::open(const std::filesystem::path& root, const std::string& id) {
  if (!isValidSessionId(id)) throw std::invalid_argument("invalid session id '" + id + "'");
  const std::filesystem::path directory = root / id;
  if (!std::filesystem::is_directory(directory))
    throw io::IoError(directory.string() + ": no such session");
  SessionInfo info = readInfo(directory);
  const std::filesystem::path journalPath = directory / kJournal;
  const std::filesystem::path missingMark = directory / kJournalMissing;
  std::error_code error;
  if (!std::filesystem::exists(journalPath, error) && !error &&
      !std::filesystem::exists(missingMark, error))
    io::writeFileAtomically(missingMark, "the journal was missing when the session was opened on " +
                                             utcNow() + "\n");
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
  if (!isValidSessionId(id)) throw std::invalid_argument("invalid session id '" + id + "'");
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

// Skipping a damaged record is safe for a sample (one sample is lost, and said), never for a
// record that changes which samples count: had it been a redo, the samples before it must not
// come back. What such a record may have changed is set aside (still in the journal, not
// counted), so the session opens, the doubt said, and a redo of the slice ends it.
void SessionStore::replay(const std::vector<io::JournalLine>& lines) {
  const std::string file = (directory_ / kJournal).string();
  std::uint64_t expected = 1;  // the "n" the next line should carry
  for (const io::JournalLine& line : lines) {
    const std::string where = file + " line " + std::to_string(line.line);
    std::optional<json> j;
    try {
      j = io::parseJson(line.text, where);
      if (!j->is_object()) throw std::invalid_argument("not a JSON object");
    } catch (const std::exception&) {
      j.reset();
    }
    // A record's number says whether lines went missing before it (or came twice).
    if (line.intact && j && j->contains("n")) {
      std::uint64_t n = 0;
      try {
        n = wholeNumber<std::uint64_t>(*j, "n", 1, std::numeric_limits<std::int64_t>::max());
      } catch (const std::exception& e) {
        setAside(line.line, where + ": unreadable record number (" + std::string(e.what()) + ")",
                 std::nullopt);
        ++expected;
        continue;
      }
      if (n > expected) {
        setAside(line.line,
                 where + ": " + std::to_string(n - expected) + " record(s) missing before it (" +
                     "numbers " + std::to_string(expected) + "-" + std::to_string(n - 1) +
                     "); any samples they held are lost",
                 std::nullopt);
      } else if (n < expected) {
        setAside(line.line,
                 where + ": record number " + std::to_string(n) + " where " +
                     std::to_string(expected) + " was expected (a line repeated or moved): skipped",
                 std::nullopt);
        continue;
      }
      expected = n + 1;
    } else {
      ++expected;
    }
    if (line.intact) {
      try {
        apply(line.text, line.line);
        continue;
      } catch (const std::exception& e) {
        // A valid checksum over content this version cannot use (a damaged writer, a newer
        // daemon): judged as a damaged record, below.
        const std::string reason = e.what();
        const std::optional<std::string> type =
            j && j->contains("t") && j->at("t").is_string()
                ? std::optional<std::string>(j->at("t").get<std::string>())
                : std::nullopt;
        std::optional<SliceId> slice;
        try {
          if (j) slice = sliceFrom(j->at("slice"));
        } catch (const std::exception&) {
        }
        if (type == "sample") {
          damage_.push_back({line.line, reason + ": the sample is not counted", {}, 0, 1});
        } else if (type == "start" || type == "stop") {
          damage_.push_back({line.line, reason + ": skipped (it changes no samples)", {}, 0, 0});
        } else {
          setAside(line.line, reason, type == "redo" ? slice : std::nullopt);
        }
        continue;
      }
    }
    // The checksum failed: what is left of the line says what it may have been.
    std::optional<std::string> type;
    std::optional<SliceId> slice;
    try {
      if (j) {
        type = j->at("t").get<std::string>();
        slice = sliceFrom(j->at("slice"));
      }
    } catch (const std::exception&) {
    }
    if (type == "sample") {
      damage_.push_back({line.line,
                         where + ": damaged sample record (checksum mismatch) skipped: " +
                             (slice ? "1 sample of " + toString(*slice) : std::string("1 sample")) +
                             " lost",
                         {},
                         0,
                         1});
    } else if (type == "start" || type == "stop") {
      damage_.push_back({line.line,
                         where + ": damaged sweep " + *type +
                             " record (checksum mismatch) skipped (it changes no samples; the "
                             "sweep in progress may be shown wrongly)",
                         {},
                         0,
                         0});
    } else {
      setAside(line.line, where + ": damaged record (checksum mismatch) that may have been a redo",
               type == "redo" ? slice : std::nullopt);
    }
  }
  nextSequence_ = expected;
}

void SessionStore::setAside(std::size_t line, std::string what, std::optional<SliceId> slice) {
  // A redo of a slice that had no samples before it may be a slice damaged into another name:
  // then it cannot be told which slice it was.
  if (slice && sampleCount(*slice) == 0 && setAsideCount(*slice) == 0) slice.reset();
  JournalDamage damage{line, std::move(what), {}, 0, 0};
  std::vector<SliceId> affected;
  if (slice) {
    affected.push_back(*slice);
  } else {
    for (const auto& [id, bins] : bins_)
      if (sampleCount(id) > 0) affected.push_back(id);
  }
  std::string names;
  for (const SliceId& id : affected) {
    const std::size_t count = sampleCount(id);
    if (count == 0) continue;
    setAside_[id] += count;
    damagedSlices_.insert(id);
    binsFor(id).clear();
    damage.slicesSetAside.push_back(id);
    damage.samplesSetAside += count;
    names += (names.empty() ? "" : ", ") + toString(id) + " (" + std::to_string(count) + ")";
  }
  if (damage.slicesSetAside.empty()) {
    damage.message += ": no earlier samples were in doubt";
  } else {
    damage.message += ": the earlier samples of " + names +
                      " are set aside (kept in the journal, not counted); a redo of the slice "
                      "sweeps it again";
  }
  damage_.push_back(std::move(damage));
}

void SessionStore::apply(const std::string& record, std::size_t line) {
  const std::string where = (directory_ / kJournal).string() + " line " + std::to_string(line);
  const json j = io::parseJson(record, where);
  try {
    const std::string type = j.at("t").get<std::string>();
    const SliceId slice = sliceFrom(j.at("slice"));
    if (type == "sample") {
      const json& light = j.at("light");
      const json& view = j.at("view");
      const json& rgb = j.at("rgb");
      binsFor(slice).add(
          {wholeNumber<std::int64_t>(j, "ts"),
           wholeNumber<std::uint64_t>(j, "frame"),
           {light.at(0).get<double>(), light.at(1).get<double>()},
           {view.at(0).get<double>(), view.at(1).get<double>()},
           {rgb.at(0).get<double>(), rgb.at(1).get<double>(), rgb.at(2).get<double>()}});
    } else if (type == "redo") {
      binsFor(slice).clear();
      damagedSlices_.erase(slice);  // what was set aside would be discarded now anyway
    } else if (type == "start") {
      activeSweep_ = slice;
    } else if (type == "stop") {
      if (activeSweep_ == slice) activeSweep_.reset();
    } else {
      throw std::invalid_argument("unknown record type \"" + type + "\"");
    }
  } catch (const std::exception& e) {
    throw io::IoError(where + ": " + e.what());
  }
}

void SessionStore::append(json record) {
  record["n"] = nextSequence_;
  journal_.append(record.dump());
  ++nextSequence_;  // only once it is on disk: a failed append is rolled back
}

void SessionStore::recordSample(const SliceId& slice, const FrameSample& s) {
  requireSweepSlice(slice);
  append(json{{"t", "sample"},
              {"slice", sliceJson(slice)},
              {"ts", s.timestampUs},
              {"frame", s.frameIndex},
              {"light", {s.light.thetaDeg, s.light.phiDeg}},
              {"view", {s.view.thetaDeg, s.view.phiDeg}},
              {"rgb", {s.value.r(), s.value.g(), s.value.b()}}});
  // durable first: only then does the sample count
  binsFor(slice).add(s);
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
  binsFor(slice).clear();
  damagedSlices_.erase(slice);
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

SliceSet SessionStore::slices() const {
  SliceSet set;
  for (const auto& [slice, bins] : bins_) {
    for (const SliceSample& sample : bins.combine())
      set.add(slice, sample);
  }
  return set;
}

}  // namespace slicecap::capture
