// Session directories: create, list, reopen, redo, resume after kill -9, errors naming the file.
#include "slicecap/capture/session_store.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

#include "../support/kill_dash_nine.hpp"
#include "../support/sweep_sample.hpp"
#include "../support/test_support.hpp"
#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::capture {
namespace {

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};
const SliceId kDiagonal7575{SliceKind::Diagonal, {75, 75}};

using test::hdrSampleAt;
using test::sampleAt;

// The record of each journal line, its checksum and space cut off.
std::vector<std::string> journalRecords(const std::filesystem::path& journal) {
  std::ifstream in(journal, std::ios::binary);
  std::vector<std::string> records;
  for (std::string line; std::getline(in, line);)
    records.push_back(line.substr(9));
  return records;
}

std::uint64_t bitsOf(double value) {
  return std::bit_cast<std::uint64_t>(value);
}

void expectBitIdentical(const Rgb& a, const Rgb& b, const std::string& what) {
  for (std::size_t c = 0; c < 3; ++c)
    EXPECT_EQ(bitsOf(a[c]), bitsOf(b[c]))
        << what << " channel " << c << ": " << a[c] << " vs " << b[c];
}

TEST(SessionStore, CreatesListsReopensAndRemoves) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "felt-1", "red felt");
    store.recordSweepStarted(kAxial3030);
    for (int k = 0; k < 24; ++k)
      store.recordSample(kAxial3030, sampleAt(k * 15.0, 0.1 * k, std::uint64_t(k)));
    store.recordSweepStopped(kAxial3030);
  }
  SessionStore::create(root, "leather", "brown leather");
  const std::vector<SessionInfo> sessions = SessionStore::list(root);
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[0].id, "felt-1");
  EXPECT_EQ(sessions[0].material, "red felt");

  const SessionStore reopened = SessionStore::open(root, "felt-1");
  EXPECT_EQ(reopened.sampleCount(), 24u);
  EXPECT_EQ(reopened.bins(kAxial3030).filledCount(), 24);
  EXPECT_FALSE(reopened.activeSweep().has_value());
  const SliceSet slices = reopened.slices();
  ASSERT_NE(slices.find(kAxial3030), nullptr);
  EXPECT_NEAR(slices.find(kAxial3030)->samples[5].value.r(), 0.5, 1e-12);

  EXPECT_THROW(SessionStore::create(root, "felt-1", "again"), io::IoError);
  SessionStore::remove(root, "leather");
  EXPECT_EQ(SessionStore::list(root).size(), 1u);
  EXPECT_THROW(SessionStore::open(root, "leather"), io::IoError);
  EXPECT_THROW(SessionStore::create(root, "../escape", "x"), capture::CaptureError);
}

// A session is its folder: a copy (a backup) or a renamed folder is listed and opened under its
// own name, never under the id its session.json was written with (the daemon keeps that id as
// the current session and deletes by it: the copy's `delete` would remove the original).
TEST(SessionStore, ACopiedSessionFolderIsItsOwnSession) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "felt-1", "red felt");
    store.recordSample(kAxial3030, sampleAt(30.0, 0.5));
  }
  std::filesystem::copy(root / "felt-1", root / "felt-1-backup");
  std::filesystem::rename(root / "felt-1", root / "felt-2");
  const std::vector<SessionInfo> sessions = SessionStore::list(root);
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[0].id, "felt-1-backup");
  EXPECT_EQ(sessions[1].id, "felt-2");
  EXPECT_EQ(sessions[1].material, "red felt");
  const SessionStore backup = SessionStore::open(root, "felt-1-backup");
  EXPECT_EQ(backup.info().id, "felt-1-backup");
  EXPECT_EQ(backup.sampleCount(), 1u);
  EXPECT_EQ(SessionStore::open(root, "felt-2").info().id, "felt-2");
}

// A "point" slice (the kind of scattered samples: no azimuth bins) is no sweep. The store refuses
// it before the journal is written: a sample record of it could not be replayed, and the session,
// with every sample taken before, would no longer open (nor would the daemon whose current
// session it is).
TEST(SessionStore, APointSliceIsRefusedAndTheSessionStillOpens) {
  const auto root = test::freshTempDir();
  const SliceId point{SliceKind::Point, {30, 30}};
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    store.recordSample(kAxial3030, sampleAt(30.0, 0.5));
    EXPECT_THROW(store.recordSweepStarted(point), capture::CaptureError);
    EXPECT_THROW(store.recordSample(point, sampleAt(45.0, 0.7)), capture::CaptureError);
    EXPECT_THROW(store.redo(point), capture::CaptureError);
    EXPECT_EQ(store.sampleCount(), 1u);
    EXPECT_FALSE(store.activeSweep().has_value());
  }
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(), 1u);
  EXPECT_EQ(store.sampleCount(kAxial3030), 1u);
  EXPECT_FALSE(store.activeSweep().has_value());
}

TEST(SessionStore, RedoDiscardsOnlyThatSliceAndPersists) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    store.recordSample(kAxial3030, sampleAt(0, 1));
    store.recordSample(kDiagonal7575, sampleAt(0, 2));
    store.redo(kAxial3030);
    store.recordSample(kAxial3030, sampleAt(30, 3));
  }
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(kAxial3030), 1u);
  EXPECT_EQ(store.sampleCount(kDiagonal7575), 1u);
  EXPECT_DOUBLE_EQ(store.slices().find(kAxial3030)->samples[0].value.r(), 3.0);
}

// A sweep refused for its decoding: its slice's samples so far stay in the journal but no table
// uses them, the reason is kept, later samples count again, and a redo ends the refusal.
TEST(SessionStore, ARefusedSweepsSamplesAreSetAsideKeptAndSaidAfterReopening) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    const std::uint64_t run = store.nextRecordNumber();
    store.recordSample(kAxial3030, sampleAt(0, 1));
    store.recordSample(kAxial3030, sampleAt(30, 2));
    store.recordSample(kDiagonal7575, sampleAt(0, 5));
    store.refuse(kAxial3030, "decoding broken: the window's G ...", run);
    EXPECT_EQ(store.sampleCount(kAxial3030), 0u);
    EXPECT_EQ(store.setAsideCount(kAxial3030), 2u);
    EXPECT_EQ(store.sampleCount(kDiagonal7575), 1u) << "another slice's samples are not the run's";
    EXPECT_THROW(store.refuse(SliceId{SliceKind::Point, {30, 30}}, "x", run),
                 capture::CaptureError);
    store.recordSample(kAxial3030, sampleAt(45, 3));  // the slice swept again: counts
  }
  SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(kAxial3030), 1u);
  EXPECT_EQ(store.setAsideCount(kAxial3030), 2u);
  EXPECT_EQ(store.sampleCount(kDiagonal7575), 1u);
  EXPECT_FALSE(store.damaged(kAxial3030)) << "a refusal is no doubt about the journal";
  EXPECT_TRUE(store.damage().empty());
  ASSERT_EQ(store.refusals().size(), 1u);
  EXPECT_EQ(store.refusals()[0].slice, kAxial3030);
  EXPECT_EQ(store.refusals()[0].samplesSetAside, 2u);
  EXPECT_EQ(store.refusals()[0].reason, "decoding broken: the window's G ...");
  ASSERT_EQ(store.slices().find(kAxial3030)->samples.size(), 1u);
  EXPECT_DOUBLE_EQ(store.slices().find(kAxial3030)->samples[0].value.r(), 3.0);
  EXPECT_EQ(store.refusedCount(kAxial3030), 2u);
  store.redo(kAxial3030);
  EXPECT_TRUE(store.refusals().empty());
  EXPECT_TRUE(SessionStore::open(root, "s").refusals().empty());
  // Why they were set aside outlives the reason: a redo does not make them journal damage.
  EXPECT_EQ(store.setAsideCount(kAxial3030), 2u);
  EXPECT_EQ(store.refusedCount(kAxial3030), 2u);
  EXPECT_EQ(SessionStore::open(root, "s").refusedCount(kAxial3030), 2u);
}

// A refusal judges one sweep run (its latest samples): the slice's earlier runs, good, keep
// counting, with their samples in the bins the refused run also filled; reopening agrees.
TEST(SessionStore, ARefusalSetsAsideTheRefusedRunsSamplesAlone) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    store.recordSweepStarted(kAxial3030);
    store.recordSample(kAxial3030, sampleAt(0, 1));
    store.recordSample(kAxial3030, sampleAt(15, 2));
    store.recordSweepStopped(kAxial3030);
    store.recordSweepStarted(kAxial3030);
    const std::uint64_t run = store.nextRecordNumber();
    store.recordSample(kAxial3030, sampleAt(0, 7));   // the same bin as the good run's first
    store.recordSample(kDiagonal7575, sampleAt(0, 5));  // no sweep of it runs; another slice
    store.recordSample(kAxial3030, sampleAt(30, 8));
    store.refuse(kAxial3030, "decoding broken", run);
    store.recordSweepStopped(kAxial3030);
    EXPECT_EQ(store.sampleCount(kAxial3030), 2u);
    EXPECT_EQ(store.refusals().back().samplesSetAside, 2u);
  }
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_TRUE(store.damage().empty());
  EXPECT_EQ(store.sampleCount(kAxial3030), 2u);
  EXPECT_EQ(store.setAsideCount(kAxial3030), 2u);
  EXPECT_EQ(store.sampleCount(kDiagonal7575), 1u);
  ASSERT_EQ(store.bins(kAxial3030).samplesIn(0).size(), 1u);
  EXPECT_DOUBLE_EQ(store.bins(kAxial3030).samplesIn(0)[0].value.r(), 1.0);
  EXPECT_EQ(store.bins(kAxial3030).samplesIn(1).size(), 1u);
  EXPECT_TRUE(store.bins(kAxial3030).samplesIn(2).empty());
  ASSERT_EQ(store.refusals().size(), 1u);
  EXPECT_EQ(store.refusals()[0].samplesSetAside, 2u);
}

// A refusal names the run's texture frames when the sweep captured a texture: they are read back
// with it (the daemon sets them aside again on opening); a refusal without them (no texture, or
// a record from before the field) reads without them. No format step: the session stays 4.
TEST(SessionStore, ARefusalKeepsTheRunsTextureFramesAcrossReopening) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    std::uint64_t run = store.nextRecordNumber();
    store.recordSample(kAxial3030, sampleAt(0, 1));
    store.refuse(kAxial3030, "decoding broken", run, RunTextureFrames{12, 30});
    run = store.nextRecordNumber();
    store.recordSample(kDiagonal7575, sampleAt(0, 2));
    store.refuse(kDiagonal7575, "decoding broken", run);
  }
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_TRUE(store.damage().empty());
  ASSERT_EQ(store.refusals().size(), 2u);
  ASSERT_TRUE(store.refusals()[0].textureFrames);
  EXPECT_EQ(store.refusals()[0].textureFrames->from, 12u);
  EXPECT_EQ(store.refusals()[0].textureFrames->to, 30u);
  EXPECT_EQ(store.refusals()[0].samplesSetAside, 1u);
  EXPECT_FALSE(store.refusals()[1].textureFrames);
  EXPECT_EQ(store.info().format, 4);
}

// A session written when a refusal set aside every sample of its slice (format 3: a `refuse`
// record without "from") still opens and reads as it was written; its next refusal marks it 4.
TEST(SessionStore, AFormatThreeRefusalStillSetsAsideEverySampleOfItsSlice) {
  const auto root = test::freshTempDir();
  std::filesystem::create_directories(root / "old");
  std::ofstream(root / "old" / "session.json")
      << R"({"format":3,"id":"old","material":"m","created":"2026-12-06T14:05:00Z"})";
  {
    io::Journal journal = io::Journal::open(root / "old" / "journal", nullptr);
    const std::string slice = R"("slice":{"kind":"axial","theta_i":30,"theta_v":30})";
    for (int n = 1; n <= 2; ++n)
      journal.append(R"({"frame":3,"light":[30.0,)" + std::to_string(15 * n) + R"(],"n":)" +
                     std::to_string(n) + R"(,"rgb":[0.5,0.5,0.5],)" + slice +
                     R"(,"t":"sample","ts":99000,"view":[30.0,60.0]})");
    journal.append(R"({"n":3,"reason":"decoding broken",)" + slice + R"(,"t":"refuse"})");
    journal.append(R"({"frame":4,"light":[30.0,90.0],"n":4,"rgb":[0.5,0.5,0.5],)" + slice +
                   R"(,"t":"sample","ts":99000,"view":[30.0,60.0]})");
  }
  SessionStore store = SessionStore::open(root, "old");
  EXPECT_TRUE(store.damage().empty());
  EXPECT_EQ(store.sampleCount(kAxial3030), 1u);
  EXPECT_EQ(store.setAsideCount(kAxial3030), 2u);
  EXPECT_EQ(store.refusedCount(kAxial3030), 2u);
  ASSERT_EQ(store.refusals().size(), 1u);
  EXPECT_EQ(store.refusals()[0].samplesSetAside, 2u);
  store.refuse(kAxial3030, "decoding broken again", store.nextRecordNumber());
  std::ifstream in(root / "old" / "session.json");
  EXPECT_NE(std::string(std::istreambuf_iterator<char>(in), {}).find("\"format\": 4"),
            std::string::npos);
}

// A version before the `refuse` record reads it as damage and sets aside every slice's samples
// before it, and one before its "from" every sample of its slice: a session is marked format 4
// with its first refusal, which such a version (it reads 1 to 2, or 1 to 3) refuses to open,
// naming the file (as AFormatOneSessionWithoutCellsStillOpens shows of a format this version
// does not know); a session without a refusal stays format 2.
TEST(SessionStore, ASessionWithARefusalIsMarkedAFormatOlderVersionsRefuse) {
  const auto root = test::freshTempDir();
  const auto formatOf = [&](const std::string& id) {
    std::ifstream in(root / id / "session.json");
    const std::string text{std::istreambuf_iterator<char>(in), {}};
    const std::size_t at = text.find("\"format\": ");
    return at == std::string::npos ? std::string("?") : text.substr(at + 10, 1);
  };
  {
    SessionStore plain = SessionStore::create(root, "plain", "m");
    plain.recordSample(kAxial3030, sampleAt(0, 1));
    SessionStore refused = SessionStore::create(root, "refused", "m");
    refused.recordSample(kAxial3030, sampleAt(0, 1));
    EXPECT_EQ(formatOf("refused"), "2");
    refused.refuse(kAxial3030, "decoding broken", 1);
  }
  EXPECT_EQ(formatOf("plain"), "2");
  EXPECT_EQ(formatOf("refused"), "4");
  SessionStore reopened = SessionStore::open(root, "refused");
  EXPECT_EQ(reopened.info().material, "m");
  EXPECT_EQ(reopened.refusals().size(), 1u);
  reopened.redo(kAxial3030);
  EXPECT_EQ(formatOf("refused"), "4") << "the journal still holds the record";
}

TEST(SessionStore, ResumesAfterKillDashNineWithEveryAcknowledgedSample) {
  const auto root = test::freshTempDir();
  SessionStore::create(root, "s", "m");
  const int acknowledged = test::killAfterAcknowledgements(200, [&](const auto& acknowledge) {
    SessionStore store = SessionStore::open(root, "s");
    store.recordSweepStarted(kDiagonal7575);
    for (std::uint64_t i = 0;; ++i) {
      store.recordSample(kDiagonal7575, sampleAt(double(i % 24) * 15.0, 1.0, i));
      acknowledge();
    }
  });
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_GE(store.sampleCount(), std::size_t(acknowledged));
  EXPECT_EQ(store.activeSweep(), kDiagonal7575) << "the interrupted sweep is the one to resume";
}

TEST(SessionStore, CorruptRecordsNameTheJournalAndTheLine) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    store.recordSample(kAxial3030, sampleAt(0, 1));
  }
  // A valid checksum over a record of an unknown type (e.g. a newer daemon's journal): the
  // session opens, the record set aside and named.
  io::Journal::open(root / "s" / "journal", nullptr)
      .append("{\"t\":\"teleport\",\"slice\":{\"kind\":\"axial\",\"theta_i\":30,\"theta_v\":30}}");
  const SessionStore store = SessionStore::open(root, "s");
  ASSERT_EQ(store.damage().size(), 1u);
  EXPECT_NE(store.damage()[0].message.find("journal line 2"), std::string::npos)
      << store.damage()[0].message;
  std::ofstream(root / "s" / "session.json") << "{\"format\":7}";
  EXPECT_THROW(SessionStore::open(root, "s"), io::IoError);
  ASSERT_EQ(SessionStore::list(root).size(), 1u) << "a session with its journal is listed";
  EXPECT_NE(SessionStore::list(root)[0].damage.find("\"format\""), std::string::npos);
}

TEST(SessionStore, AnUnopenableDescriptionSaysWhy) {
  const auto root = test::freshTempDir();
  SessionStore::create(root, "s", "m");
  std::filesystem::remove(root / "s" / "session.json");
  try {
    SessionStore::open(root, "s");
    FAIL();
  } catch (const io::IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("session.json: cannot open session description"), std::string::npos)
        << message;
    EXPECT_NE(message.find(std::strerror(ENOENT)), std::string::npos) << message;
  }
}

// Found by tests/fuzz/journal_fuzz: nlohmann's get<int>() of 1e300 is undefined behaviour and its
// get<std::uint64_t>() of -1 wraps round, so such records were taken as some other number.
TEST(SessionStore, ANumberOutOfItsRangeNamesTheRecordAndTheField) {
  const std::string slice = R"("slice":{"kind":"axial","theta_i":30,"theta_v":30})";
  const std::string sample = R"("light":[30,0],"view":[30,15],"rgb":[1,1,1])";
  struct Case {
    std::string record, field;
  };
  const std::vector<Case> cases = {
      {R"({"t":"start","slice":{"kind":"axial","theta_i":1e300,"theta_v":30}})", "theta_i"},
      {R"({"t":"start","slice":{"kind":"axial","theta_i":30,"theta_v":-1}})", "theta_v"},
      {R"({"t":"start","slice":{"kind":"axial","theta_i":30.5,"theta_v":30}})", "theta_i"},
      {R"({"t":"sample",)" + slice + R"(,"ts":1e300,"frame":1,)" + sample + "}", "ts"},
      {R"({"t":"sample",)" + slice + R"(,"ts":1,"frame":-1,)" + sample + "}", "frame"},
  };
  for (const Case& c : cases) {
    const auto root = test::freshTempDir();
    SessionStore::create(root, "s", "m");
    io::Journal::open(root / "s" / "journal", nullptr).append(c.record);
    const SessionStore store = SessionStore::open(root, "s");
    ASSERT_EQ(store.damage().size(), 1u) << c.record;
    const std::string expected = "journal line 1: " + c.field + ": expected a whole number";
    EXPECT_NE(store.damage()[0].message.find(expected), std::string::npos)
        << store.damage()[0].message;
  }
  // The messages print the value: one nested too deep for nlohmann's recursive dump is refused
  // when the record is parsed.
  const auto root = test::freshTempDir();
  SessionStore::create(root, "s", "m");
  io::Journal::open(root / "s" / "journal", nullptr)
      .append(R"({"t":"start","slice":{"kind":"axial","theta_i":)" + std::string(200000, '[') +
              std::string(200000, ']') + R"(,"theta_v":30}})");
  const SessionStore store = SessionStore::open(root, "s");
  ASSERT_EQ(store.damage().size(), 1u);
  EXPECT_NE(store.damage()[0].message.find("journal line 1: not valid JSON"), std::string::npos)
      << store.damage()[0].message;
  // The session's description: a format of 1.5 is not format 1.
  std::ofstream(root / "s" / "session.json")
      << R"({"format":1.5,"id":"s","material":"m","created":"2026-11-23T14:05:00Z"})";
  EXPECT_THROW(SessionStore::open(root, "s"), io::IoError);
}

// A single-exposure sample's record is the one journals held before HDR readings were kept: old
// and new journals are one format.
TEST(SessionStore, ASampleWithoutAReadingWritesTheRecordItAlwaysHas) {
  const auto root = test::freshTempDir();
  SessionStore::create(root, "s", "m").recordSample(kAxial3030, sampleAt(45.0, 0.5, 3));
  const std::vector<std::string> records = journalRecords(root / "s" / "journal");
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0],
            R"({"frame":3,"light":[30.0,45.0],"n":1,"rgb":[0.5,0.5,0.5],)"
            R"("slice":{"kind":"axial","theta_i":30,"theta_v":30},"t":"sample","ts":99000,)"
            R"("view":[30.0,60.0]})");
}

// Every double of a reading reads back with the same bits (nlohmann writes the shortest form that
// round-trips and reads with strtod): random bit patterns over the whole range, subnormals and
// -0 among them.
TEST(SessionStore, AnHdrReadingReplaysBitIdentical) {
  const auto root = test::freshTempDir();
  std::mt19937_64 random(31);
  const auto anyFinite = [&] {
    for (;;) {
      const double value = std::bit_cast<double>(random());
      if (std::isfinite(value)) return value;
    }
  };
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  std::vector<FrameSample> written;
  for (std::uint64_t i = 0; i < 24; ++i) {
    FrameSample s = hdrSampleAt(double(i) * 15.0, 2.0, 16.0, int(i % 3), i);
    for (HdrCell& cell : s.hdr->cells) {
      for (std::size_t c = 0; c < 3; ++c) {
        cell.radiance[c] = anyFinite();
        cell.variance[c] = std::abs(anyFinite());
      }
      cell.level = fraction(random);
    }
    s.hdr->cells[0].radiance = {-0.0, std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::max()};
    s.hdr->cells[1].radiance = {0.1, 1.0 / 3.0, -std::numeric_limits<double>::min()};
    s.hdr->irradiance = {anyFinite(), anyFinite(), anyFinite()};
    s.hdr->irradianceWeight = std::abs(anyFinite());
    written.push_back(s);
  }
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    for (const FrameSample& s : written)
      store.recordSample(kAxial3030, s);
  }
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_TRUE(store.damage().empty());
  const AzimuthBins& bins = store.bins(kAxial3030);
  ASSERT_EQ(store.sampleCount(), written.size());
  for (const FrameSample& w : written) {
    const std::vector<FrameSample>& bin = bins.samplesIn(bins.binOf(w));
    ASSERT_EQ(bin.size(), 1u);
    const FrameSample& r = bin[0];
    ASSERT_TRUE(r.hdr.has_value()) << "frame " << w.frameIndex << " replayed without its reading";
    EXPECT_EQ(r.hdr->exposureLevel, w.hdr->exposureLevel);
    ASSERT_EQ(r.hdr->cells.size(), w.hdr->cells.size());
    for (std::size_t k = 0; k < w.hdr->cells.size(); ++k) {
      const std::string cell =
          "frame " + std::to_string(w.frameIndex) + " cell " + std::to_string(k);
      expectBitIdentical(r.hdr->cells[k].radiance, w.hdr->cells[k].radiance, cell + " radiance");
      expectBitIdentical(r.hdr->cells[k].variance, w.hdr->cells[k].variance, cell + " variance");
      EXPECT_EQ(bitsOf(r.hdr->cells[k].level), bitsOf(w.hdr->cells[k].level)) << cell;
      EXPECT_EQ(r.hdr->cells[k].clipped, w.hdr->cells[k].clipped) << cell;
    }
    expectBitIdentical(r.hdr->irradiance, w.hdr->irradiance, "irradiance");
    EXPECT_EQ(bitsOf(r.hdr->irradianceWeight), bitsOf(w.hdr->irradianceWeight));
  }
}

// The point of keeping the readings: a daemon restarted mid-sweep merges the exposures per cell
// as before its restart. A long exposure that clips and a short one per bin: the merge reads the
// short one's cells, the median of the two frames' values would not.
TEST(SessionStore, TheMergedBinsAfterReopeningAreThoseBefore) {
  const auto root = test::freshTempDir();
  SliceSet before, withoutCells;
  {
    SessionStore store = SessionStore::create(root, "hdr", "m");
    SessionStore plain = SessionStore::create(root, "plain", "m");
    for (std::uint64_t i = 0; i < 24; ++i) {
      const double radiance = 1.7 + 0.0123 * double(i);
      for (const FrameSample& s :
           {hdrSampleAt(double(i) * 15.0 + 1.1, radiance, 16.0, 0, 2 * i),
            hdrSampleAt(double(i) * 15.0 + 2.3, radiance, 0.25, 1, 2 * i + 1)}) {
        store.recordSample(kAxial3030, s);
        FrameSample noCells = s;
        noCells.hdr.reset();
        plain.recordSample(kAxial3030, noCells);
      }
    }
    before = store.slices();
    withoutCells = plain.slices();
  }
  const SliceSet after = SessionStore::open(root, "hdr").slices();
  ASSERT_NE(before.find(kAxial3030), nullptr);
  ASSERT_NE(after.find(kAxial3030), nullptr);
  const std::vector<SliceSample>& b = before.find(kAxial3030)->samples;
  const std::vector<SliceSample>& a = after.find(kAxial3030)->samples;
  const std::vector<SliceSample>& p = withoutCells.find(kAxial3030)->samples;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(p.size(), b.size());
  for (std::size_t k = 0; k < b.size(); ++k) {
    expectBitIdentical(a[k].value, b[k].value, "bin " + std::to_string(k));
    EXPECT_EQ(bitsOf(a[k].light.phiDeg), bitsOf(b[k].light.phiDeg)) << k;
    EXPECT_EQ(bitsOf(a[k].view.phiDeg), bitsOf(b[k].view.phiDeg)) << k;
    // The cells matter: without them the bin is the median of a clipped and a true value.
    EXPECT_GT(std::abs(p[k].value.r() - b[k].value.r()), 0.01 * b[k].value.r()) << "bin " << k;
  }
}

// A reading that would not replay (a NaN is written as null) is refused before it is written: a
// sample counted now and lost on the next open would be worse.
TEST(SessionStore, AnHdrReadingThatWouldNotReplayIsRefusedAndNothingWritten) {
  const auto root = test::freshTempDir();
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    store.recordSample(kAxial3030, hdrSampleAt(15.0, 0.5, 1.0, 0, 1));
    FrameSample bad = hdrSampleAt(30.0, 0.5, 1.0, 0, 2);
    bad.hdr->cells[4].radiance[1] = std::numeric_limits<double>::quiet_NaN();
    try {
      store.recordSample(kAxial3030, bad);
      FAIL() << "a NaN radiance was recorded";
    } catch (const capture::CaptureError& e) {
      EXPECT_NE(std::string(e.what()).find("frame 2"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("hdr.cells[4][1] (radiance g)"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(store.sampleCount(), 1u);
  }
  EXPECT_EQ(journalRecords(root / "s" / "journal").size(), 1u);
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_EQ(store.sampleCount(), 1u);
  EXPECT_TRUE(store.damage().empty());
}

// A sample at sampleAt's angles with a 3 x 3 window of cells (values at cellPrecision, as the
// pipeline keeps them), the middle one clipped.
FrameSample sampleWithCells(double parameterDeg, std::uint64_t frame) {
  FrameSample s = sampleAt(parameterDeg, 0.5, frame);
  WindowCells cells;
  cells.cellsPerSide = 3;
  cells.gridMm = {-16.5, -16.25, 16.5, 16.75};
  cells.lightMm = {12.5, -210.25, 190.125};
  cells.cameraMm = {-120.0 / 7.0, 250.0 / 3.0, 260.0 / 11.0};
  for (int k = 0; k < 9; ++k)
    cells.cells.push_back({{},
                           {},
                           Rgb{cellPrecision(0.1 + k / 7.0), cellPrecision(0.2 / (k + 1)), 0.0},
                           Rgb::gray(cellPrecision(1e-5 * (k + 1) / 3.0)),
                           k == 4});
  placeCellDirections(cells);
  s.cells = std::move(cells);
  return s;
}

// The window's cells replay with the same bits (directions recomputed from the same geometry),
// and the session's slices carry the cell reading after reopening as before.
TEST(SessionStore, WindowCellsReplayBitIdentical) {
  const auto root = test::freshTempDir();
  const FrameSample recorded = sampleWithCells(45.0, 7);
  SliceSet before;
  {
    SessionStore store = SessionStore::create(root, "s", "m");
    store.recordSample(kAxial3030, recorded);
    before = store.slices();
  }
  ASSERT_TRUE(before.hasCellSamples());
  const SessionStore store = SessionStore::open(root, "s");
  EXPECT_TRUE(store.damage().empty());
  const std::vector<FrameSample>& bin = store.bins(kAxial3030).samplesIn(3);
  ASSERT_EQ(bin.size(), 1u);
  ASSERT_TRUE(bin[0].cells);
  const WindowCells& a = *recorded.cells;
  const WindowCells& b = *bin[0].cells;
  EXPECT_EQ(b.cellsPerSide, 3);
  EXPECT_EQ(b.gridMm, a.gridMm);
  EXPECT_EQ(b.lightMm, a.lightMm);
  EXPECT_EQ(b.cameraMm, a.cameraMm);
  ASSERT_EQ(b.cells.size(), a.cells.size());
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    const std::string cell = "cell " + std::to_string(k);
    expectBitIdentical(b.cells[k].value, a.cells[k].value, cell + " value");
    expectBitIdentical(b.cells[k].variance, a.cells[k].variance, cell + " variance");
    EXPECT_EQ(bitsOf(b.cells[k].light.thetaDeg), bitsOf(a.cells[k].light.thetaDeg)) << cell;
    EXPECT_EQ(bitsOf(b.cells[k].view.phiDeg), bitsOf(a.cells[k].view.phiDeg)) << cell;
    EXPECT_EQ(b.cells[k].clipped, a.cells[k].clipped) << cell;
  }
  const SliceSet after = store.slices();
  ASSERT_EQ(after.slices().size(), 1u);
  ASSERT_EQ(after.slices()[0].cellSamples.size(), before.slices()[0].cellSamples.size());
  for (std::size_t k = 0; k < after.slices()[0].cellSamples.size(); ++k)
    expectBitIdentical(after.slices()[0].cellSamples[k].value,
                       before.slices()[0].cellSamples[k].value, "cell sample");
}

// A session written before cells (format 1, samples without "cells") still opens, its samples
// the window centres alone.
TEST(SessionStore, AFormatOneSessionWithoutCellsStillOpens) {
  const auto root = test::freshTempDir();
  std::filesystem::create_directories(root / "old");
  std::ofstream(root / "old" / "session.json")
      << R"({"format":1,"id":"old","material":"m","created":"2026-11-23T14:05:00Z"})";
  io::Journal::open(root / "old" / "journal", nullptr)
      .append(R"({"frame":3,"light":[30.0,45.0],"n":1,"rgb":[0.5,0.5,0.5],)"
              R"("slice":{"kind":"axial","theta_i":30,"theta_v":30},"t":"sample","ts":99000,)"
              R"("view":[30.0,60.0]})");
  const SessionStore store = SessionStore::open(root, "old");
  EXPECT_TRUE(store.damage().empty());
  EXPECT_EQ(store.sampleCount(), 1u);
  EXPECT_FALSE(store.bins(kAxial3030).samplesIn(3).at(0).cells);
  EXPECT_FALSE(store.slices().hasCellSamples());
  // A format this version does not know is refused, naming the file and what it reads.
  std::ofstream(root / "old" / "session.json")
      << R"({"format":5,"id":"old","material":"m","created":"2026-11-23T14:05:00Z"})";
  try {
    SessionStore::open(root, "old");
    FAIL() << "format 5 opened";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 1 to 4"), std::string::npos) << e.what();
  }
}

TEST(SessionStore, CellsThatWouldNotReplayAreRefusedAndNothingWritten) {
  const auto root = test::freshTempDir();
  SessionStore store = SessionStore::create(root, "s", "m");
  FrameSample bad = sampleWithCells(30.0, 2);
  bad.cells->cells[5].variance[2] = -1e-6;
  try {
    store.recordSample(kAxial3030, bad);
    FAIL() << "a negative variance was recorded";
  } catch (const capture::CaptureError& e) {
    EXPECT_NE(std::string(e.what()).find("cells.values[5][5] (variance b)"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(store.sampleCount(), 0u);
  EXPECT_TRUE(journalRecords(root / "s" / "journal").empty());
}

}  // namespace
}  // namespace slicecap::capture
