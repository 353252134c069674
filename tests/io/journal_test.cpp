// The journal: records survive reopening, kill -9 and a torn or failed write; atomic replacement.
#include "slicecap/io/journal.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "../support/file_size_limit.hpp"
#include "../support/kill_dash_nine.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

std::vector<std::string> reopen(const std::filesystem::path& path,
                                JournalRecovery* recovery = nullptr) {
  std::vector<std::string> records;
  Journal::open(path, &records, recovery);
  return records;
}

TEST(Journal, KeepsRecordsAcrossReopens) {
  const auto path = test::freshTempDir() / "session.journal";
  {
    std::vector<std::string> records;
    Journal journal = Journal::open(path, &records);
    EXPECT_TRUE(records.empty());
    journal.append("{\"sample\":1}");
    journal.append("");
    journal.append("caf\xc3\xa9");
  }
  Journal journal = Journal::open(path, nullptr);
  journal.append("fourth");
  EXPECT_EQ(reopen(path),
            (std::vector<std::string>{"{\"sample\":1}", "", "caf\xc3\xa9", "fourth"}));
  EXPECT_THROW(journal.append("two\nlines"), io::IoError);
}

TEST(Journal, CutsATornTailAndSkipsCorruptLines) {
  const auto path = test::freshTempDir() / "j";
  {
    Journal journal = Journal::open(path, nullptr);
    journal.append("one");
    journal.append("two");
    journal.append("three");
  }
  // A crash mid-append leaves a partial last line; bit rot flips a byte in the second record.
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.find("two")] = 'T';
  bytes += "1234abcd half a rec";
  std::ofstream(path, std::ios::binary) << bytes;
  JournalRecovery recovery;
  EXPECT_EQ(reopen(path, &recovery), (std::vector<std::string>{"one", "three"}));
  EXPECT_EQ(recovery.records, 2u);
  EXPECT_EQ(recovery.tornTailBytes, 19u);
  EXPECT_EQ(recovery.corruptLines, std::vector<std::size_t>{2});
  // The tail is gone from disk, and appending continues cleanly after it.
  Journal::open(path, nullptr).append("four");
  EXPECT_EQ(reopen(path).back(), "four");
}

TEST(Journal, KeepsTheTornTailAndGivesDamagedLinesWithTheirNumbers) {
  const auto path = test::freshTempDir() / "j";
  {
    Journal journal = Journal::open(path, nullptr);
    journal.append("one");
    journal.append("redo");
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.find("redo")] = 'x';
  std::ofstream(path, std::ios::binary) << bytes << "1234abcd half";
  std::vector<JournalLine> lines;
  JournalRecovery recovery;
  Journal::openLines(path, &lines, &recovery);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].line, 1u);
  EXPECT_TRUE(lines[0].intact);
  EXPECT_EQ(lines[0].text, "one");
  EXPECT_EQ(lines[1].line, 2u);
  EXPECT_FALSE(lines[1].intact) << "a damaged line is given, for its reader to judge";
  EXPECT_EQ(lines[1].text, "xedo");
  // The cut-off bytes are not deleted: they are kept beside the journal.
  std::ifstream kept(tornTailFile(path), std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "1234abcd half");
}

TEST(Journal, AFailedAppendLeavesEveryEarlierRecordIntact) {
  const auto path = test::freshTempDir() / "j";
  Journal journal = Journal::open(path, nullptr);
  journal.append("kept");
  const auto size = std::filesystem::file_size(path);
  // A file-size limit makes the next write fail as a full disk would (EFBIG instead of ENOSPC).
  {
    const test::FileSizeLimit limit(size + 10);
    EXPECT_THROW(journal.append(std::string(100, 'x')), IoError);
  }
  EXPECT_EQ(std::filesystem::file_size(path), size) << "the partial record was cut back";
  journal.append("after");
  EXPECT_EQ(reopen(path), (std::vector<std::string>{"kept", "after"}));
}

TEST(Journal, AcknowledgedRecordsSurviveKillDashNine) {
  const auto path = test::freshTempDir() / "j";
  const int acknowledged = test::killAfterAcknowledgements(300, [&](const auto& acknowledge) {
    Journal journal = Journal::open(path, nullptr);
    for (int i = 0;; ++i) {
      journal.append("record " + std::to_string(i) + std::string(200, '.'));
      acknowledge();
    }
  });
  const std::vector<std::string> records = reopen(path);
  ASSERT_GE(records.size(), std::size_t(acknowledged));
  for (std::size_t i = 0; i < records.size(); ++i)
    EXPECT_EQ(records[i].rfind("record " + std::to_string(i) + ".", 0), 0u);
}

TEST(Journal, OpenErrorsNameThePath) {
  try {
    Journal::open("/nonexistent-dir/j", nullptr);
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/j"), std::string::npos);
  }
}

TEST(AtomicFile, ReplacesWholeFilesOnly) {
  const auto dir = test::freshTempDir();
  writeFileAtomically(dir / "state.json", "{\"old\":true}");
  writeFileAtomically(dir / "state.json", "{\"new\":true}");
  std::ifstream in(dir / "state.json");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "{\"new\":true}");
  EXPECT_FALSE(std::filesystem::exists(dir / "state.json.tmp"));
  EXPECT_THROW(writeFileAtomically(dir / "missing" / "x", "y"), IoError);
}

TEST(DurableFolders, CreateNestedAndDiscardWholeTreesLeavingNoHalf) {
  namespace fs = std::filesystem;
  const fs::path root = test::freshTempDir();
  createFoldersDurably(root / "a" / "b" / "c");
  EXPECT_TRUE(fs::is_directory(root / "a" / "b" / "c"));
  createFoldersDurably(root / "a" / "b" / "c");  // already there: nothing to do
  std::ofstream(root / "a" / "b" / "c" / "frame") << "x";
  // A discard cut off earlier left its renamed folder: the next one replaces it.
  fs::create_directories(root / (std::string("a") + kDiscardedSuffix) / "old");
  discardFolderDurably(root / "a");
  EXPECT_FALSE(fs::exists(root / "a"));
  EXPECT_FALSE(fs::exists(root / (std::string("a") + kDiscardedSuffix)));
  EXPECT_NO_THROW(discardFolderDurably(root / "a"));  // gone already
  std::ofstream(root / "file") << "x";
  EXPECT_THROW(createFoldersDurably(root / "file" / "sub"), IoError);
}

TEST(Crc32, MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);
}

}  // namespace
}  // namespace slicecap::io
