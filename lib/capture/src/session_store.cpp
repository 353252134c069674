// Session directories: atomic description, replayed journal of samples and sweep events.
#include "slicecap/capture/session_store.hpp"

#include <algorithm>
#include <chrono>
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
  std::ifstream in(file);
  if (!in) throw io::IoError(file.string() + ": cannot open session description");
  const json j = io::parseJson(std::string(std::istreambuf_iterator<char>(in), {}), file.string());
  if (!j.is_object()) throw io::IoError(file.string() + ": not a JSON object");
  try {
    if (!j.at("format").is_number_integer() || j.at("format") != kFormatVersion) {
      throw io::IoError(file.string() + ": field \"format\" is " + j.at("format").dump() +
                        ", expected 1");
    }
    static_cast<void>(j.at("id").get<std::string>());  // required: else not a session
    return {directory.filename().string(), j.at("material").get<std::string>(),
            j.at("created").get<std::string>()};
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
  SessionInfo info{id, material, utcNow()};
  io::writeFileAtomically(directory / "session.json",
                          json{{"format", kFormatVersion},
                               {"id", id},
                               {"material", material},
                               {"created", info.createdUtc}}
                              .dump(2, ' ', false, json::error_handler_t::replace));
  return SessionStore(directory, std::move(info),
                      io::Journal::open(directory / "journal", nullptr));
}

SessionStore SessionStore::open(const std::filesystem::path& root, const std::string& id) {
  if (!isValidSessionId(id)) throw std::invalid_argument("invalid session id '" + id + "'");
  const std::filesystem::path directory = root / id;
  if (!std::filesystem::is_directory(directory))
    throw io::IoError(directory.string() + ": no such session");
  SessionInfo info = readInfo(directory);
  std::vector<std::string> records;
  io::JournalRecovery recovery;
  io::Journal journal = io::Journal::open(directory / "journal", &records, &recovery);
  SessionStore store(directory, std::move(info), std::move(journal));
  store.recovery_ = recovery;
  for (std::size_t i = 0; i < records.size(); ++i)
    store.apply(records[i], i + 1);
  return store;
}

std::vector<SessionInfo> SessionStore::list(const std::filesystem::path& root) {
  std::vector<SessionInfo> sessions;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(root, error)) {
    if (!entry.is_directory() || !isValidSessionId(entry.path().filename().string())) continue;
    try {
      sessions.push_back(readInfo(entry.path()));
    } catch (const io::IoError&) {
      // A half-created or foreign folder is not a session.
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

void SessionStore::apply(const std::string& record, std::size_t recordNumber) {
  const std::string where =
      (directory_ / "journal").string() + ": record " + std::to_string(recordNumber);
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

void SessionStore::recordSample(const SliceId& slice, const FrameSample& s) {
  requireSweepSlice(slice);
  const std::string record = json{{"t", "sample"},
                                  {"slice", sliceJson(slice)},
                                  {"ts", s.timestampUs},
                                  {"frame", s.frameIndex},
                                  {"light", {s.light.thetaDeg, s.light.phiDeg}},
                                  {"view", {s.view.thetaDeg, s.view.phiDeg}},
                                  {"rgb", {s.value.r(), s.value.g(), s.value.b()}}}
                                 .dump();
  journal_.append(record);  // durable first: only then does the sample count
  binsFor(slice).add(s);
}

void SessionStore::recordSweepStarted(const SliceId& slice) {
  requireSweepSlice(slice);
  journal_.append(json{{"t", "start"}, {"slice", sliceJson(slice)}}.dump());
  activeSweep_ = slice;
}

void SessionStore::recordSweepStopped(const SliceId& slice) {
  journal_.append(json{{"t", "stop"}, {"slice", sliceJson(slice)}}.dump());
  if (activeSweep_ == slice) activeSweep_.reset();
}

void SessionStore::redo(const SliceId& slice) {
  requireSweepSlice(slice);
  journal_.append(json{{"t", "redo"}, {"slice", sliceJson(slice)}}.dump());
  binsFor(slice).clear();
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
