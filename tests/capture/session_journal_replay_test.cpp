// A session whose journal is damaged: a record that may have changed which samples count is never
// skipped silently (its slice's earlier samples are set aside), and every loss names file and line.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/sweep_sample.hpp"
#include "../support/test_support.hpp"
#include "slicecap/capture/session_store.hpp"

namespace slicecap::capture {
namespace {

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};
const SliceId kDiagonal3030{SliceKind::Diagonal, {30, 30}};

using test::sampleAt;

std::vector<std::string> journalLines(const std::filesystem::path& journal) {
  std::ifstream in(journal, std::ios::binary);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  return lines;
}

void writeLines(const std::filesystem::path& journal, const std::vector<std::string>& lines) {
  std::ofstream out(journal, std::ios::binary | std::ios::trunc);
  for (const std::string& line : lines)
    out << line << "\n";
}

// 1-based line of the first record of `type`.
std::size_t lineOf(const std::vector<std::string>& lines, const std::string& type) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].find("\"t\":\"" + type + "\"") != std::string::npos) return i + 1;
  ADD_FAILURE() << "no " << type << " record";
  return 0;
}

// A diagonal 30/30 sweep of 11 samples, a redo of it, then 3 samples; 2 axial samples before.
std::filesystem::path sessionWithRedo() {
  const auto root = test::freshTempDir();
  SessionStore store = SessionStore::create(root, "s", "m");
  store.recordSample(kAxial3030, sampleAt(0, 1, 0));
  store.recordSample(kAxial3030, sampleAt(15, 1, 1));
  store.recordSweepStarted(kDiagonal3030);
  for (std::uint64_t i = 0; i < 11; ++i)
    store.recordSample(kDiagonal3030, sampleAt(double(i) * 15, 5, 10 + i));
  store.redo(kDiagonal3030);
  for (std::uint64_t i = 0; i < 3; ++i)
    store.recordSample(kDiagonal3030, sampleAt(double(i) * 15, 7, 30 + i));
  store.recordSweepStopped(kDiagonal3030);
  return root;
}

std::string allDamage(const SessionStore& store) {
  std::string text;
  for (const JournalDamage& damage : store.damage())
    text += damage.message + "\n";
  return text;
}

TEST(SessionJournalDamage, AFlippedByteInARedoNeverBringsItsSamplesBack) {
  // The byte in the record's type, then in its slice (theta 30 -> 31: still a slice, no longer
  // one with samples), then in the checksum.
  for (const std::string flip : {"\"redo\"", "\"theta_i\":30", "checksum"}) {
    SCOPED_TRACE(flip);
    const auto root = sessionWithRedo();
    const auto journal = root / "s" / "journal";
    std::vector<std::string> lines = journalLines(journal);
    const std::size_t redoLine = lineOf(lines, "redo");
    std::string& redo = lines[redoLine - 1];
    if (flip == "checksum")
      redo[0] = redo[0] == '0' ? '1' : '0';
    else
      redo[redo.find(flip, 9) + (flip == "\"redo\"" ? 2 : 11)] += 1;
    writeLines(journal, lines);

    const SessionStore store = SessionStore::open(root, "s");
    EXPECT_EQ(store.sampleCount(kDiagonal3030), 3u) << "the discarded sweep's samples came back";
    EXPECT_EQ(store.setAsideCount(kDiagonal3030), 11u);
    EXPECT_TRUE(store.damaged(kDiagonal3030));
    ASSERT_FALSE(store.damage().empty());
    EXPECT_EQ(store.damage().front().line, redoLine);
    EXPECT_NE(allDamage(store).find(journal.string() + " line " + std::to_string(redoLine)),
              std::string::npos)
        << allDamage(store);
    EXPECT_NE(allDamage(store).find("set aside"), std::string::npos) << allDamage(store);
  }
}

TEST(SessionJournalDamage, ADamagedSampleRecordCostsThatSampleOnly) {
  const auto root = sessionWithRedo();
  const auto journal = root / "s" / "journal";
  std::vector<std::string> lines = journalLines(journal);
  const std::size_t line = lineOf(lines, "sample");              // the first axial sample
  lines[line - 1][lines[line - 1].find("\"rgb\"") + 7] ^= 0x01;  // still JSON, a wrong value
  writeLines(journal, lines);
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(kAxial3030), 1u);
  EXPECT_EQ(store.sampleCount(kDiagonal3030), 3u);
  EXPECT_FALSE(store.damaged(kAxial3030)) << "a lost sample puts no other sample in doubt";
  ASSERT_EQ(store.damage().size(), 1u);
  EXPECT_EQ(store.damage()[0].samplesLost, 1u);
  EXPECT_NE(store.damage()[0].message.find(" line " + std::to_string(line)), std::string::npos);
}

TEST(SessionJournalDamage, ADroppedRedoLineIsSeenByTheGapInRecordNumbers) {
  const auto root = sessionWithRedo();
  const auto journal = root / "s" / "journal";
  std::vector<std::string> lines = journalLines(journal);
  const std::size_t redoLine = lineOf(lines, "redo");
  lines.erase(lines.begin() + std::ptrdiff_t(redoLine - 1));
  writeLines(journal, lines);
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(kDiagonal3030), 3u) << "the discarded sweep's samples came back";
  ASSERT_FALSE(store.damage().empty());
  EXPECT_NE(allDamage(store).find("missing"), std::string::npos) << allDamage(store);
  // The gap is said again on the next open, and new records go on numbering after it.
  {
    SessionStore reopened = SessionStore::open(root, "s");
    reopened.recordSample(kAxial3030, sampleAt(45, 1, 99));
  }
  const SessionStore again = SessionStore::open(root, "s");
  EXPECT_EQ(again.damage().size(), store.damage().size()) << allDamage(again);
  EXPECT_EQ(again.sampleCount(kAxial3030), 1u) << "the set-aside axial samples stay set aside";
}

TEST(SessionJournalDamage, ARecordWithAValidChecksumButBadContentIsSetAsideNotFatal) {
  const auto root = sessionWithRedo();
  std::size_t lineCount = journalLines(root / "s" / "journal").size();
  io::Journal::open(root / "s" / "journal", nullptr)
      .append(R"({"t":"teleport","slice":{"kind":"diagonal","theta_i":30,"theta_v":30}})");
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(), 0u) << "an unknown record may have changed any slice";
  EXPECT_EQ(store.setAsideCount(kDiagonal3030), 3u);
  EXPECT_EQ(store.setAsideCount(kAxial3030), 2u);
  ASSERT_EQ(store.damage().size(), 1u);
  EXPECT_EQ(store.damage()[0].line, lineCount + 1);
  EXPECT_NE(store.damage()[0].message.find("unknown record type \"teleport\""), std::string::npos)
      << store.damage()[0].message;
  // A redo afterwards ends the doubt about that slice.
  {
    SessionStore reopened = SessionStore::open(root, "s");
    reopened.redo(kDiagonal3030);
    reopened.recordSample(kDiagonal3030, sampleAt(0, 9, 50));
  }
  const SessionStore redone = SessionStore::open(root, "s");
  EXPECT_FALSE(redone.damaged(kDiagonal3030));
  EXPECT_TRUE(redone.damaged(kAxial3030));
  EXPECT_EQ(redone.sampleCount(kDiagonal3030), 1u);
}

TEST(SessionJournalDamage, ADeletedJournalIsSaidOnEveryOpen) {
  const auto root = sessionWithRedo();
  std::filesystem::remove(root / "s" / "journal");
  for (int open = 0; open < 2; ++open) {
    const SessionStore store = SessionStore::open(root, "s");
    EXPECT_EQ(store.sampleCount(), 0u);
    EXPECT_NE(allDamage(store).find((root / "s" / "journal").string() + ": was missing"),
              std::string::npos)
        << allDamage(store);
  }
}

TEST(SessionJournalDamage, ATornTailIsKeptAndSaid) {
  const auto root = sessionWithRedo();
  std::ofstream(root / "s" / "journal", std::ios::app | std::ios::binary) << "0badf00d {\"t\":\"sa";
  for (int open = 0; open < 2; ++open) {
    const SessionStore store = SessionStore::open(root, "s");
    EXPECT_EQ(store.sampleCount(kDiagonal3030), 3u);
    EXPECT_NE(allDamage(store).find("unfinished record"), std::string::npos) << allDamage(store);
  }
  std::ifstream kept(io::tornTailFile(root / "s" / "journal"), std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "0badf00d {\"t\":\"sa");
}

TEST(SessionJournalDamage, ASessionWithADamagedDescriptionIsListedAsDamaged) {
  const auto root = sessionWithRedo();
  std::ofstream(root / "s" / "session.json") << "{\"format\":";
  std::filesystem::create_directory(root / "not-a-session");
  // As a crash between making the journal and the description leaves a new session's folder.
  std::filesystem::create_directory(root / "half-made");
  std::ofstream(root / "half-made" / "journal").close();
  const std::vector<SessionInfo> sessions = SessionStore::list(root);
  ASSERT_EQ(sessions.size(), 1u) << "a folder without a journal's records is still no session";
  EXPECT_EQ(sessions[0].id, "s");
  EXPECT_NE(sessions[0].damage.find("session.json"), std::string::npos) << sessions[0].damage;
}

// An HDR sample's record whose reading is damaged, yet whose checksum holds (a damaged writer): the
// sample is not counted and the line is named, never counted without its cells (its bin would
// then be merged as a single exposure's, from a value that may be clipped).
TEST(SessionJournalDamage, ADamagedHdrReadingCostsThatSampleAndNamesTheLine) {
  using nlohmann::json;
  struct Case {
    std::string name;
    std::function<void(json&)> damage;
    std::string said;
  };
  const std::vector<Case> cases = {
      {"35 cells", [](json& hdr) { hdr["cells"].erase(hdr["cells"].size() - 1); },
       "hdr.cells: expected an array of 36 cells, got 35 cells"},
      {"a NaN written as null", [](json& hdr) { hdr["cells"][7][2] = nullptr; },
       "hdr.cells[7][2] (radiance b): expected a number, got null"},
      {"a negative variance", [](json& hdr) { hdr["cells"][3][4] = -1e-6; },
       "hdr.cells[3][4] (variance g): expected a variance >= 0, got -1e-06"},
      {"clipped not a bool", [](json& hdr) { hdr["cells"][0][7] = 1; },
       "hdr.cells[0][7] (clipped): expected true or false, got 1"},
      {"a level beyond full scale", [](json& hdr) { hdr["cells"][5][6] = 7.5; },
       "hdr.cells[5][6] (level): expected a fraction of full scale"},
      {"exposure level 3", [](json& hdr) { hdr["exposure_level"] = 3; },
       "hdr.exposure_level: expected a whole number in 0..2, got 3"},
      {"a negative irradiance weight", [](json& hdr) { hdr["irradiance_weight"] = -2.5; },
       "hdr.irradiance_weight: expected >= 0, got -2.5"},
      {"no cells", [](json& hdr) { hdr.erase("cells"); }, "hdr.cells: missing"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto root = test::freshTempDir();
    {
      SessionStore store = SessionStore::create(root, "s", "m");
      store.recordSample(kAxial3030, test::hdrSampleAt(0, 0.5, 1.0, 0, 1));
      store.recordSample(kAxial3030, test::hdrSampleAt(15, 0.5, 1.0, 1, 2));
    }
    const auto journal = root / "s" / "journal";
    std::vector<std::string> lines = journalLines(journal);
    ASSERT_EQ(lines.size(), 2u);
    json record = json::parse(lines[1].substr(9));
    c.damage(record.at("hdr"));
    lines.pop_back();
    writeLines(journal, lines);
    io::Journal::open(journal, nullptr).append(record.dump());  // a valid checksum

    const SessionStore store = SessionStore::open(root, "s");
    EXPECT_EQ(store.sampleCount(kAxial3030), 1u) << "the damaged sample was counted";
    ASSERT_EQ(store.damage().size(), 1u) << allDamage(store);
    EXPECT_EQ(store.damage()[0].line, 2u);
    EXPECT_EQ(store.damage()[0].samplesLost, 1u);
    EXPECT_NE(allDamage(store).find(journal.string() + " line 2: " + c.said), std::string::npos)
        << allDamage(store);
    EXPECT_NE(allDamage(store).find("the sample is not counted"), std::string::npos)
        << allDamage(store);
  }
}

}  // namespace
}  // namespace slicecap::capture
