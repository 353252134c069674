// Replaying a session's journal: records applied in order, damaged or missing ones judged by what
// they may have changed (a sample lost, or the samples they may have changed set aside).
#include <nlohmann/json.hpp>

#include "journal_records.hpp"
#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::capture {
namespace {

using nlohmann::json;
using namespace journal_records;

// What can still be read of a record that cannot be applied: its type and slice, when readable.
struct RecordRemains {
  std::optional<std::string> type;
  std::optional<SliceId> slice;
};

RecordRemains remainsOf(const std::optional<json>& j) {
  RecordRemains out;
  if (!j) return out;
  if (j->contains("t") && j->at("t").is_string()) out.type = j->at("t").get<std::string>();
  try {
    out.slice = sliceFrom(j->at("slice"));
  } catch (const std::exception&) {
  }
  return out;
}

// A sample record's sample. An HDR sample's reading ("hdr", absent from single-exposure
// records and from journals written before it) is checked whole: a damaged one makes the record
// damaged, never a sample without its cells, which the bin would merge differently.
FrameSample sampleFrom(const json& j) {
  const json& light = j.at("light");
  const json& view = j.at("view");
  const json& rgb = j.at("rgb");
  FrameSample sample{wholeNumber<std::int64_t>(j, "ts"),
                     wholeNumber<std::uint64_t>(j, "frame"),
                     {light.at(0).get<double>(), light.at(1).get<double>()},
                     {view.at(0).get<double>(), view.at(1).get<double>()},
                     {rgb.at(0).get<double>(), rgb.at(1).get<double>(), rgb.at(2).get<double>()}};
  if (j.contains("hdr")) sample.hdr = hdrFrom(j.at("hdr"));
  // The window's cells (session format 2); absent from older records, which stay centres only.
  if (j.contains("cells")) sample.cells = cellsFrom(j.at("cells"));
  return sample;
}

// A line's JSON, parsed once: an HDR sample's reading makes a record ~30 times longer, and
// parsing is most of the time a session takes to open. Else why it is not JSON.
struct ParsedRecord {
  std::optional<json> value;
  std::string error;
};

ParsedRecord parseRecord(const std::string& text, const std::string& where) {
  try {
    return {io::parseJson(text, where), {}};
  } catch (const std::exception& e) {
    return {std::nullopt, e.what()};
  }
}

}  // namespace

// Skipping a damaged record is safe for a sample (one sample is lost, and said), never for a
// record that changes which samples count: had it been a redo, the samples before it must not
// come back. What such a record may have changed is set aside (still in the journal, not
// counted), so the session opens, the doubt said, and a redo of the slice ends it.
void SessionStore::replay(const std::vector<io::JournalLine>& lines) {
  const std::string file = (directory_ / kJournal).string();
  std::uint64_t expected = 1;  // the "n" the next line should carry
  for (const io::JournalLine& line : lines) {
    const std::string where = file + " line " + std::to_string(line.line);
    const ParsedRecord parsed = parseRecord(line.text, where);
    const std::optional<json>& j = parsed.value;
    if (!acceptRecordNumber(line, j, where, expected)) continue;
    if (line.intact) {
      try {
        if (!j) throw io::IoError(parsed.error);
        apply(*j, line.line, expected - 1);  // acceptRecordNumber moved past its number
      } catch (const std::exception& e) {
        // A valid checksum over content this version cannot use (a damaged writer, a newer
        // daemon): judged as a damaged record.
        const RecordRemains remains = remainsOf(j);
        judgeUnusableRecord(line.line, e.what(), remains.type, remains.slice);
      }
      continue;
    }
    // The checksum failed: what is left of the line says what it may have been.
    const RecordRemains remains = remainsOf(j);
    judgeDamagedRecord(line.line, where, remains.type, remains.slice);
  }
  nextSequence_ = expected;
}

// A record's number says whether lines went missing before it (or came twice).
bool SessionStore::acceptRecordNumber(const io::JournalLine& line, const std::optional<json>& j,
                                      const std::string& where, std::uint64_t& expected) {
  if (!line.intact || !j || !j->contains("n")) {
    ++expected;
    return true;
  }
  std::uint64_t n = 0;
  try {
    n = wholeNumber<std::uint64_t>(*j, "n", 1, std::numeric_limits<std::int64_t>::max());
  } catch (const std::exception& e) {
    setAside(line.line, where + ": unreadable record number (" + std::string(e.what()) + ")",
             std::nullopt);
    ++expected;
    return false;
  }
  if (n > expected) {
    setAside(line.line,
             where + ": " + std::to_string(n - expected) + " record(s) missing before it (" +
                 "numbers " + std::to_string(expected) + "-" + std::to_string(n - 1) +
                 "); any samples they held are lost",
             std::nullopt);
  } else if (n < expected) {
    setAside(line.line,
             where + ": record number " + std::to_string(n) + " where " + std::to_string(expected) +
                 " was expected (a line repeated or moved): skipped",
             std::nullopt);
    return false;
  }
  expected = n + 1;
  return true;
}

void SessionStore::judgeUnusableRecord(std::size_t line, const std::string& reason,
                                       const std::optional<std::string>& type,
                                       const std::optional<SliceId>& slice) {
  if (type == "sample") {
    damage_.push_back({line, reason + ": the sample is not counted", {}, 0, 1});
  } else if (type == "start" || type == "stop") {
    damage_.push_back({line, reason + ": skipped (it changes no samples)", {}, 0, 0});
  } else {
    setAside(line, reason, type == "redo" || type == "refuse" ? slice : std::nullopt);
  }
}

void SessionStore::judgeDamagedRecord(std::size_t line, const std::string& where,
                                      const std::optional<std::string>& type,
                                      const std::optional<SliceId>& slice) {
  if (type == "sample") {
    damage_.push_back({line,
                       where + ": damaged sample record (checksum mismatch) skipped: " +
                           (slice ? "1 sample of " + toString(*slice) : std::string("1 sample")) +
                           " lost",
                       {},
                       0,
                       1});
  } else if (type == "start" || type == "stop") {
    damage_.push_back({line,
                       where + ": damaged sweep " + *type +
                           " record (checksum mismatch) skipped (it changes no samples; the "
                           "sweep in progress may be shown wrongly)",
                       {},
                       0,
                       0});
  } else {
    setAside(line, where + ": damaged record (checksum mismatch) that may have been a redo",
             type == "redo" || type == "refuse" ? slice : std::nullopt);
  }
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
    damage.slicesSetAside.push_back(id);
    damage.samplesSetAside += count;
    uncountAll(id);
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

void SessionStore::apply(const json& j, std::size_t line, std::uint64_t number) {
  const std::string where = (directory_ / kJournal).string() + " line " + std::to_string(line);
  try {
    const std::string type = j.at("t").get<std::string>();
    const SliceId slice = sliceFrom(j.at("slice"));
    if (type == "sample") {
      countSample(slice, sampleFrom(j), number);
    } else if (type == "redo") {
      uncountAll(slice);
      damagedSlices_.erase(slice);  // what was set aside would be discarded now anyway
      forgetRefusals(slice);
    } else if (type == "refuse") {
      // Format 4 names the refused run's first record; a format 3 record refused every counted
      // sample of its slice, and still does.
      std::optional<std::uint64_t> first;
      if (j.contains("from")) first = wholeNumber<std::uint64_t>(j, "from");
      // The run's texture frames, from texture capture; absent from older records and without it.
      std::optional<RunTextureFrames> texture;
      if (j.contains("texture_from"))
        texture = RunTextureFrames{wholeNumber<std::uint64_t>(j, "texture_from"),
                                   wholeNumber<std::uint64_t>(j, "texture_to")};
      applyRefusal(slice, j.at("reason").get<std::string>(), first, texture);
    } else if (type == "start") {
      activeSweep_ = slice;
    } else if (type == "stop") {
      if (activeSweep_ == slice) activeSweep_.reset();
    } else {
      throw CaptureError("unknown record type \"" + type + "\"");
    }
  } catch (const std::exception& e) {
    throw io::IoError(where + ": " + e.what());
  }
}

}  // namespace slicecap::capture
