// The on-disk texture store the daemon captures into: the same bins as the in-memory ones, every
// kept frame durable, bounded files, and what a crash or a damaged file leaves mended on opening.
#include "slicecap/btf/texture_store.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "../support/test_support.hpp"
#include "slicecap/btf/btf_error.hpp"
#include "slicecap/btf/texture_capture.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/sim/patterned_material.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::btf {
namespace {

namespace fs = std::filesystem;

const SliceId kAxial{SliceKind::Axial, {30, 75}};
const SliceId kDiagonal{SliceKind::Diagonal, {75, 75}};
const TextureStoreLayout kLayout{2, {-10.0, -10.0, 10.0, 10.0}, 3};  // 4 texels, 3 frames a bin

TextureFrame frameAt(double parameterDeg, float value) {
  TextureFrame frame{parameterDeg, {1.0, 2.0, 300.0}, {0.0, 100.0, 280.0 + value}, {}};
  for (int i = 0; i < 12; ++i)
    frame.texels.push_back(value + 0.125f * static_cast<float>(i));
  frame.texels[5] = std::numeric_limits<float>::quiet_NaN();  // a texel the frame did not see
  return frame;
}

std::vector<fs::path> frameFiles(const fs::path& directory) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(directory))
    if (entry.path().extension() == ".tex") files.push_back(entry.path());
  return files;
}

TEST(TextureStore, KeepsTheSameFramesAsTheInMemoryBinsAndCombinesThemAlike) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore store = TextureStore::openOrCreate(dir, kLayout);
  SliceTextureBins memory(kAxial, 4, kLayout.framesPerBin);
  // Bin 1 (15 deg) gets five frames; the three nearest its centre are kept.
  const double parameters[] = {21.0, 9.0, 16.0, 14.0, 7.6, 200.0};
  float value = 1.0f;
  for (double p : parameters) {
    const TextureFrame frame = frameAt(p, value);
    value *= 2.0f;
    const bool keep = store.wouldKeep(kAxial, p);  // asked before, as the daemon does
    EXPECT_EQ(store.add(kAxial, frame), keep) << p;
    memory.add(frame);
  }
  EXPECT_EQ(store.frameCount(kAxial), 4u);  // 3 in bin 1, 1 in bin 13
  EXPECT_EQ(store.filledBins(kAxial), 2);
  EXPECT_EQ(frameFiles(dir).size(), 4u);  // the replaced frames' files are gone
  EXPECT_FALSE(store.wouldKeep(kAxial, 22.0));  // farther than every kept frame of its full bin
  EXPECT_TRUE(store.wouldKeep(kAxial, 15.5));   // nearer: it would replace the farthest
  EXPECT_TRUE(store.wouldKeep(kAxial, 100.0));  // an empty bin

  const std::vector<SliceTexture> stored = store.combine();
  const SliceTexture expected = memory.combine();
  ASSERT_EQ(stored.size(), 1u);
  ASSERT_EQ(stored[0].bins.size(), expected.bins.size());
  for (std::size_t b = 0; b < expected.bins.size(); ++b) {
    EXPECT_EQ(stored[0].bins[b].frames, expected.bins[b].frames) << "bin " << b;
    if (expected.bins[b].frames == 0) continue;
    EXPECT_TRUE(stored[0].bins[b].cameraMm.isApprox(expected.bins[b].cameraMm));
    EXPECT_TRUE(stored[0].bins[b].lightMm.isApprox(expected.bins[b].lightMm));
    for (std::size_t i = 0; i < 12; ++i) {
      const float want = expected.bins[b].texels[i];
      if (std::isnan(want)) {
        EXPECT_TRUE(std::isnan(stored[0].bins[b].texels[i]));
      } else {
        EXPECT_NEAR(stored[0].bins[b].texels[i], want, 1e-3 * want);  // half floats on disk
      }
    }
  }
  EXPECT_THROW(store.add(kAxial, TextureFrame{0.0, {}, {}, std::vector<float>(3, 1.0f)}),
               btf::BtfError);
}

TEST(TextureStore, ReopeningGivesEveryStoredFrameBackAndNumbersOnFromThere) {
  const fs::path dir = test::freshTempDir() / "texture";
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    store.add(kAxial, frameAt(0.0, 1.0f));
    store.add(kDiagonal, frameAt(90.0, 2.0f));
  }  // the daemon killed here: nothing more than what add() returned from
  TextureStore store = TextureStore::open(dir);
  EXPECT_EQ(store.frameCount(), 2u);
  EXPECT_EQ(store.slices(), (std::vector<SliceId>{kAxial, kDiagonal}));
  store.add(kAxial, frameAt(1.0, 3.0f));
  EXPECT_EQ(frameFiles(dir).size(), 3u);  // a new number, not an overwritten frame
  EXPECT_EQ(TextureStore::open(dir).frameCount(), 3u);
  EXPECT_EQ(store.layout().resolution, 2);
  EXPECT_EQ(store.layout().framesPerBin, 3);
  EXPECT_TRUE(store.layout().windowMm == kLayout.windowMm);
}

TEST(TextureStore, AnotherResolutionForTheSameSessionIsRefusedNamingTheManifest) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore::openOrCreate(dir, kLayout).add(kAxial, frameAt(0.0, 1.0f));
  TextureStoreLayout other = kLayout;
  other.resolution = 4;
  try {
    TextureStore::openOrCreate(dir, other);
    FAIL() << "another resolution was accepted";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("texture.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("2 texels across"), std::string::npos) << e.what();
  }
  EXPECT_EQ(TextureStore::open(dir).frameCount(), 1u);  // nothing lost by the refusal
  EXPECT_THROW(TextureStore::open(test::freshTempDir()), io::IoError);
  TextureStoreLayout bad = kLayout;
  bad.framesPerBin = 0;
  EXPECT_THROW(TextureStore::openOrCreate(test::freshTempDir() / "t", bad), btf::BtfError);
}

TEST(TextureStore, AnUnknownTexelEncodingOrQuantityIsRefusedNamingTheFileAndField) {
  // They were not read at all: a store of float32 texels or of radiance was silently misread.
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore::openOrCreate(dir, kLayout).add(kAxial, frameAt(0.0, 1.0f));
  const fs::path manifest = dir / kTextureStoreManifest;
  const nlohmann::json written = nlohmann::json::parse(std::ifstream(manifest));
  for (const auto& [field, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"texel_encoding", "float32le"}, {"quantity", "radiance"}, {"quantity", nullptr}}) {
    nlohmann::json changed = written;
    if (value.is_null())
      changed.erase(field);
    else
      changed[field] = value;
    std::ofstream(manifest) << changed.dump(2);
    for (const StoreAccess access : {StoreAccess::ReadOnly, StoreAccess::Mend}) {
      try {
        TextureStore::open(dir, access);
        ADD_FAILURE() << field << " " << value.dump() << " was accepted";
      } catch (const io::IoError& e) {
        EXPECT_NE(std::string(e.what()).find(manifest.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      }
    }
  }
  EXPECT_EQ(frameFiles(dir).size(), 1u) << "a refused store is left as it was";
  std::ofstream(manifest) << written.dump(2);
  EXPECT_EQ(TextureStore::open(dir).frameCount(), 1u);
}

// The message naming a wrong version printed it, with nlohmann's recursive dump: a value nested
// 200000 deep overflowed the stack.
TEST(TextureStore, AManifestNestedTooDeepIsRefusedNamingIt) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore::openOrCreate(dir, kLayout);
  const fs::path manifest = dir / kTextureStoreManifest;
  std::ofstream(manifest) << R"({"format": "slicecap-texture-store", "version": )"
                          << std::string(200000, '[') << std::string(200000, ']') << "}";
  try {
    TextureStore::open(dir, StoreAccess::ReadOnly);
    ADD_FAILURE() << "no error";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(manifest.string() + ": not valid JSON"), std::string::npos)
        << e.what();
  }
}

// Seen with tests/fuzz/texture_store_fuzz: they were read with nlohmann's get<int>(), undefined
// behaviour for 1e300 and 128 for 128.7.
TEST(TextureStore, AResolutionOrFramesPerBinThatIsNoWholeNumberIsRefusedNamingTheField) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore::openOrCreate(dir, kLayout).add(kAxial, frameAt(0.0, 1.0f));
  const fs::path manifest = dir / kTextureStoreManifest;
  const nlohmann::json written = nlohmann::json::parse(std::ifstream(manifest));
  for (const auto& [field, value] :
       std::vector<std::pair<std::string, nlohmann::json>>{{"resolution", 1e300},
                                                           {"resolution", 2.5},
                                                           {"resolution", 4294967298u},
                                                           {"frames_per_bin", -1e300},
                                                           {"frames_per_bin", 3.5}}) {
    nlohmann::json changed = written;
    changed[field] = value;
    std::ofstream(manifest) << changed.dump(2);
    try {
      TextureStore::open(dir, StoreAccess::ReadOnly);
      ADD_FAILURE() << field << " " << value.dump() << " was accepted";
    } catch (const io::IoError& e) {
      EXPECT_NE(std::string(e.what()).find(manifest.string() + ": " + field), std::string::npos)
          << e.what();
    }
  }
  std::ofstream(manifest) << written.dump(2);
  EXPECT_EQ(TextureStore::open(dir).frameCount(), 1u);
}

TEST(TextureStore, OpeningMendsWhatACrashLeftAndDropsDamagedFrames) {
  const fs::path dir = test::freshTempDir() / "texture";
  fs::path evicted;
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    store.add(kAxial, frameAt(15.0, 1.0f));
    store.add(kAxial, frameAt(16.0, 2.0f));
    store.add(kAxial, frameAt(20.0, 4.0f));
    store.add(kAxial, frameAt(60.0, 8.0f));
    ASSERT_EQ(frameFiles(dir).size(), 4u);
    store.add(kAxial, frameAt(14.0, 16.0f));  // replaces the frame at 20 deg
  }
  const std::vector<fs::path> before = frameFiles(dir);
  ASSERT_EQ(before.size(), 4u);
  // Resurrect an older frame at 21 deg with an early sequence number, as if its deletion had
  // been lost: the keep rule must drop it again.
  {
    TextureStore scratch = TextureStore::openOrCreate(dir.parent_path() / "scratch", kLayout);
    scratch.add(kAxial, frameAt(21.0, 32.0f));
    evicted = dir / "axial-30-75" / "b01-00000000.tex";
    fs::copy_file(frameFiles(scratch.directory()).front(), evicted);
  }
  // A temporary of a write cut off, a half-discarded slice, a torn and a damaged frame.
  std::ofstream(dir / "axial-30-75" / "b02-00000099.tex.tmp") << "partial";
  fs::create_directories(dir / "diagonal-75-75.discarded");
  std::ofstream(dir / "diagonal-75-75.discarded" / "b00-00000007.tex") << "old";
  fs::path torn;
  for (const fs::path& f : before)
    if (f.filename().string().rfind("b04-", 0) == 0) torn = f;  // the frame at 60 deg
  ASSERT_FALSE(torn.empty());
  fs::resize_file(torn, fs::file_size(torn) - 10);
  // A frame in another slice's folder is wrong content too: dropped, not a failed opening.
  fs::create_directories(dir / "axial-75-75");
  const fs::path misplaced = dir / "axial-75-75" / "b01-00000042.tex";
  fs::copy_file(before.front() == torn ? before.back() : before.front(), misplaced);

  const TextureStore store = TextureStore::open(dir);
  EXPECT_EQ(store.recovery().droppedFiles.size(), 2u);  // the torn and the misplaced frame
  EXPECT_FALSE(fs::exists(misplaced));
  EXPECT_EQ(store.recovery().leftovers, 3u);  // tmp, discarded slice, the evicted frame
  EXPECT_FALSE(fs::exists(evicted));
  EXPECT_FALSE(fs::exists(torn));
  EXPECT_FALSE(fs::exists(dir / "diagonal-75-75.discarded"));
  EXPECT_EQ(store.frameCount(kAxial), 3u);
  EXPECT_EQ(store.filledBins(kAxial), 1);

  // A frame damaged after opening is named when the texels are read.
  const fs::path damaged = frameFiles(dir).front();
  {
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(100);
    const char byte = static_cast<char>(f.get());
    f.seekp(100);
    f.put(static_cast<char>(~byte));
  }
  try {
    store.combine();
    FAIL() << "a damaged frame was read";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(damaged.filename().string()), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
}

TEST(TextureStore, AFrameWithANonFiniteCameraOrLedPositionIsDroppedNamingIt) {
  // The frames' checksums are right (the writer does not look at the positions), but every texel
  // direction comes from them: reading one stopped `slicecap btf` with "zero-length vector".
  const fs::path dir = test::freshTempDir() / "texture";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    store.add(kAxial, frameAt(15.0, 1.0f));
    TextureFrame camera = frameAt(16.0, 2.0f);
    camera.cameraMm.y() = nan;
    store.add(kAxial, camera);
    TextureFrame led = frameAt(17.0, 4.0f);
    led.lightMm.z() = inf;
    store.add(kAxial, led);
  }
  const TextureStore reader = TextureStore::open(dir, StoreAccess::ReadOnly);
  const std::vector<std::string>& dropped = reader.recovery().droppedFiles;
  ASSERT_EQ(dropped.size(), 2u);
  const auto mentions = [&](const std::string& what) {
    return std::count_if(dropped.begin(), dropped.end(), [&](const std::string& message) {
      return message.find(what) != std::string::npos && message.find(".tex") != std::string::npos;
    });
  };
  EXPECT_EQ(mentions("camera position is not a finite number"), 1) << dropped[0] << dropped[1];
  EXPECT_EQ(mentions("LED position is not a finite number"), 1) << dropped[0] << dropped[1];
  const std::vector<SliceTexture> combined = reader.combine();
  ASSERT_EQ(combined.size(), 1u);
  EXPECT_EQ(combined[0].bins[1].frames, 1);
  EXPECT_TRUE(combined[0].bins[1].cameraMm.allFinite());
  EXPECT_TRUE(combined[0].bins[1].lightMm.allFinite());
}

TEST(TextureStore, AReaderChangesNothingAndReadsWhatTheKeepRuleKeeps) {
  const fs::path dir = test::freshTempDir() / "texture";
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    store.add(kAxial, frameAt(15.0, 1.0f));
    store.add(kAxial, frameAt(16.0, 2.0f));
    store.add(kAxial, frameAt(17.0, 4.0f));
  }
  // A frame the daemon is writing (its temporary) and a replaced frame not yet deleted.
  std::ofstream(dir / "axial-30-75" / "b01-00000009.tex.tmp") << "partial";
  {
    TextureStore scratch = TextureStore::openOrCreate(dir.parent_path() / "scratch", kLayout);
    scratch.add(kAxial, frameAt(21.0, 32.0f));
    fs::copy_file(frameFiles(scratch.directory()).front(), dir / "axial-30-75" / "b01-00000000.tex");
  }
  const TextureStore reader = TextureStore::open(dir, StoreAccess::ReadOnly);
  EXPECT_EQ(reader.frameCount(kAxial), 3u);
  EXPECT_EQ(reader.recovery().leftovers, 2u);
  EXPECT_TRUE(fs::exists(dir / "axial-30-75" / "b01-00000009.tex.tmp"));
  EXPECT_TRUE(fs::exists(dir / "axial-30-75" / "b01-00000000.tex"));
  EXPECT_EQ(reader.combine()[0].bins[1].frames, 3);
  TextureStore copy = reader;
  EXPECT_THROW(copy.add(kAxial, frameAt(15.0, 1.0f)), std::logic_error);
  EXPECT_THROW(copy.discard(kAxial), std::logic_error);
}

TEST(TextureStore, ARedoneSweepLosesItsFramesAndOnlyThose) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore store = TextureStore::openOrCreate(dir, kLayout);
  store.add(kAxial, frameAt(0.0, 1.0f));
  store.add(kDiagonal, frameAt(0.0, 1.0f));
  store.discard(kAxial);
  EXPECT_EQ(store.frameCount(kAxial), 0u);
  EXPECT_EQ(store.frameCount(kDiagonal), 1u);
  EXPECT_FALSE(fs::exists(dir / "axial-30-75"));
  EXPECT_EQ(TextureStore::open(dir).slices(), std::vector<SliceId>{kDiagonal});
  store.discard(kAxial);  // nothing left: no error
}

// A refused sweep run's frames are set aside: out of the index and of every store opened on the
// folder (kept in the slice's set-aside folder), the slice's earlier run's frames kept, and the
// bins the refused run held free for a later run.
TEST(TextureStore, ARefusedRunsFramesAreSetAsideAndOnlyThose) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore store = TextureStore::openOrCreate(dir, kLayout);
  store.add(kAxial, frameAt(0.0, 1.0f));     // the good run
  store.add(kDiagonal, frameAt(0.0, 1.0f));  // another slice
  const std::uint64_t run = store.nextSequence();
  store.add(kAxial, frameAt(1.0, 2.0f));  // the refused run: bin 0 beside the good frame
  store.add(kAxial, frameAt(30.0, 4.0f));
  EXPECT_EQ(store.setAside(kAxial, run), 2u);
  EXPECT_EQ(store.frameCount(kAxial), 1u);
  EXPECT_EQ(store.frameCount(kDiagonal), 1u);
  EXPECT_EQ(store.filledBins(kAxial), 1);
  EXPECT_EQ(frameFiles(dir / (std::string("axial-30-75") + io::kSetAsideSuffix)).size(), 2u);
  const TextureStore reopened = TextureStore::open(dir);
  EXPECT_EQ(reopened.frameCount(kAxial), 1u);
  EXPECT_TRUE(reopened.recovery().droppedFiles.empty());
  EXPECT_EQ(reopened.recovery().leftovers, 0u);
  ASSERT_EQ(reopened.combine().size(), 2u);
  EXPECT_NEAR(reopened.combine()[0].bins[0].texels[0], 1.0f, 1e-3);  // the good run's frame
  EXPECT_TRUE(store.wouldKeep(kAxial, 30.0)) << "the refused run's bin is free again";
  EXPECT_EQ(store.setAside(kAxial, store.nextSequence()), 0u);
}

// Bin 1 (15 deg) full with a good run's three frames; a second run begun, its frame at 14 deg
// replaces the one at 20 deg (value 2, the bin's median). Returns the second run's first
// sequence number.
std::uint64_t fillThenReplaceInASecondRun(TextureStore& store) {
  store.beginRun(kAxial);
  store.add(kAxial, frameAt(15.0, 1.0f));
  store.add(kAxial, frameAt(16.0, 4.0f));
  store.add(kAxial, frameAt(20.0, 2.0f));
  store.keepRun(kAxial);
  const std::uint64_t run = store.beginRun(kAxial);
  EXPECT_TRUE(store.add(kAxial, frameAt(14.0, 16.0f)));
  return run;
}

// Texel 0 of the slice's bin 1, as combined (the median of the bin's frames).
float binOneTexel(const TextureStore& store) {
  const std::vector<SliceTexture> combined = store.combine();
  EXPECT_EQ(combined.size(), 1u);
  return combined.empty() ? 0.0f : combined[0].bins[1].texels[0];
}

// A refused run's frame took the place of an earlier run's: the earlier frame is held, not
// deleted, and the refusal puts it back in its bin; the good run's texture is whole again.
TEST(TextureStore, ARefusedRunGivesBackTheEarlierFramesItReplaced) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore store = TextureStore::openOrCreate(dir, kLayout);
  const std::uint64_t run = fillThenReplaceInASecondRun(store);
  EXPECT_EQ(store.frameCount(kAxial), 3u);
  EXPECT_EQ(frameFiles(dir / (std::string("axial-30-75") + io::kHeldSuffix)).size(), 1u);
  EXPECT_EQ(store.setAside(kAxial, run, store.nextSequence()), 1u);
  EXPECT_EQ(store.frameCount(kAxial), 3u) << "the frame at 20 deg is back";
  EXPECT_NEAR(binOneTexel(store), 2.0f, 1e-3) << "the median of 1, 4 and 2";
  EXPECT_EQ(frameFiles(dir / "axial-30-75").size(), 3u);
  EXPECT_EQ(frameFiles(dir / (std::string("axial-30-75") + io::kHeldSuffix)).size(), 0u);
  const TextureStore reopened = TextureStore::open(dir);
  EXPECT_EQ(reopened.frameCount(kAxial), 3u);
  EXPECT_EQ(reopened.recovery().leftovers, 0u);
  EXPECT_NEAR(binOneTexel(reopened), 2.0f, 1e-3);
}

// A kept run deletes what it replaced: the bin holds its frames alone, nothing stays held.
TEST(TextureStore, AKeptRunDeletesTheEarlierFramesItReplaced) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureStore store = TextureStore::openOrCreate(dir, kLayout);
  fillThenReplaceInASecondRun(store);
  store.keepRun(kAxial);
  EXPECT_EQ(frameFiles(dir).size(), 3u);
  EXPECT_NEAR(binOneTexel(store), 4.0f, 1e-3) << "the median of 1, 4 and 16";
  EXPECT_EQ(store.setAside(kAxial, store.nextSequence()), 0u);
  EXPECT_EQ(frameFiles(dir).size(), 3u);
}

// A refused run whose frames cannot be set aside (a file where the set-aside folder goes): the
// camera stopping afterwards (keepRun) must not delete the earlier run's frame the run replaced,
// which is then its only copy; settling the journal's refusal later gives it back.
TEST(TextureStore, AFailedSetAsideLeavesTheReplacedFramesHeldForSettling) {
  const fs::path dir = test::freshTempDir() / "texture";
  const fs::path held = dir / (std::string("axial-30-75") + io::kHeldSuffix);
  const fs::path setAside = dir / (std::string("axial-30-75") + io::kSetAsideSuffix);
  TextureRun run{kAxial, 0, 0};
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    run.fromSequence = fillThenReplaceInASecondRun(store);
    run.toSequence = store.nextSequence();
    std::ofstream(setAside) << "in the way";
    EXPECT_THROW(store.setAside(kAxial, run.fromSequence, run.toSequence), io::IoError);
    store.keepRun(kAxial);
    EXPECT_EQ(frameFiles(held).size(), 1u) << "the earlier run's frame is still held";
  }
  fs::remove(setAside);
  TextureStore store = TextureStore::open(dir);
  EXPECT_EQ(store.settleRuns({run}), 1u);
  EXPECT_EQ(store.frameCount(kAxial), 3u);
  EXPECT_NEAR(binOneTexel(store), 2.0f, 1e-3) << "the median of 1, 4 and the held 2";
}

// A refused run's range reaching past its files (numbers that failed writes used): settling
// numbers the next frames past the range, so re-applying the refusal never takes a later kept
// run's frame; a store opened with the refusals does too.
TEST(TextureStore, FramesAfterSettlingAreNumberedPastTheRefusedRanges) {
  const fs::path dir = test::freshTempDir() / "texture";
  TextureRun refused{kAxial, 0, 0};
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    refused.fromSequence = store.beginRun(kAxial);
    store.add(kAxial, frameAt(30.0, 1.0f));
    refused.toSequence = store.nextSequence() + 5;
  }
  TextureStore store = TextureStore::open(dir);
  ASSERT_LT(store.nextSequence(), refused.toSequence) << "the files alone number inside it";
  EXPECT_EQ(store.settleRuns({refused}), 1u);
  EXPECT_GE(store.nextSequence(), refused.toSequence);
  store.beginRun(kAxial);
  ASSERT_TRUE(store.add(kAxial, frameAt(60.0, 2.0f)));
  store.keepRun(kAxial);
  EXPECT_EQ(store.settleRuns({refused}), 0u) << "the kept run's frame stays";
  EXPECT_EQ(store.frameCount(kAxial), 1u);
  const TextureStore reopened = TextureStore::open(dir, StoreAccess::Mend, {refused});
  EXPECT_EQ(reopened.frameCount(kAxial), 1u);
  EXPECT_GE(reopened.nextSequence(), refused.toSequence);
}

// A refused run's frame left in the slice's folder (its set-aside failed) while a later run was
// kept into the slots it left: opening with the journal's refusals sets it aside before the keep
// rule, so it does not displace the kept run's frame (the rule would delete that one).
TEST(TextureStore, OpeningSetsAsideRefusedFramesBeforeTheKeepRule) {
  const fs::path dir = test::freshTempDir() / "texture";
  const fs::path setAside = dir / (std::string("axial-30-75") + io::kSetAsideSuffix);
  TextureRun refused{kAxial, 0, 0};
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    refused.fromSequence = fillThenReplaceInASecondRun(store);  // 15, 16 kept; 14 refused
    refused.toSequence = store.nextSequence();
    std::ofstream(setAside) << "in the way";
    EXPECT_THROW(store.setAside(kAxial, refused.fromSequence, refused.toSequence), io::IoError);
    fs::remove(setAside);
    store.beginRun(kAxial);
    ASSERT_TRUE(store.add(kAxial, frameAt(20.5, 8.0f)));  // the slot the refused frame left
    store.keepRun(kAxial);
  }
  ASSERT_EQ(frameFiles(dir / "axial-30-75").size(), 4u) << "over the bin's 3: 14 still there";
  const TextureStore store = TextureStore::open(dir, StoreAccess::Mend, {refused});
  EXPECT_EQ(store.frameCount(kAxial), 3u);
  EXPECT_EQ(frameFiles(dir / "axial-30-75").size(), 3u) << "the kept run's frame stays";
  EXPECT_EQ(frameFiles(setAside).size(), 1u) << "the refused frame set aside";
  EXPECT_NEAR(binOneTexel(store), 4.0f, 1e-3) << "the median of 1, 4 and 8";
}

// A crash before the run was judged: the store opens with the run's frames (the held frame not
// read), and settling decides the held frame by the journal: no refusal of its run (the run counts
// as kept) deletes it, a refusal of the run (journaled before the crash) sets the run's frames
// aside and puts it back. Settling again changes nothing.
TEST(TextureStore, SettlingAfterACrashJudgesTheHeldFramesByTheJournalsRefusals) {
  for (const bool refused : {false, true}) {
    const fs::path dir = test::freshTempDir() / "texture";
    TextureRun run{kAxial, 0, 0};
    {
      TextureStore store = TextureStore::openOrCreate(dir, kLayout);
      run.fromSequence = fillThenReplaceInASecondRun(store);
      run.toSequence = store.nextSequence();
    }
    TextureStore store = TextureStore::open(dir);
    EXPECT_EQ(store.frameCount(kAxial), 3u);
    EXPECT_NEAR(binOneTexel(store), 4.0f, 1e-3) << "1, 4 and the unjudged run's 16";
    EXPECT_GT(store.nextSequence(), run.fromSequence);
    std::vector<TextureRun> refusals;
    if (refused) refusals.push_back(run);
    EXPECT_EQ(store.settleRuns(refusals), refused ? 1u : 0u);
    EXPECT_EQ(store.frameCount(kAxial), 3u);
    EXPECT_NEAR(binOneTexel(store), refused ? 2.0f : 4.0f, 1e-3) << refused;
    const fs::path setAside = dir / (std::string("axial-30-75") + io::kSetAsideSuffix);
    EXPECT_EQ(fs::exists(setAside) ? frameFiles(setAside).size() : 0u, refused ? 1u : 0u);
    EXPECT_EQ(frameFiles(dir).size(), refused ? 4u : 3u) << "held frame back or deleted";
    EXPECT_FALSE(fs::exists(dir / (std::string("axial-30-75") + io::kHeldSuffix)));
    EXPECT_EQ(store.settleRuns(refusals), 0u) << "settled already";
    EXPECT_EQ(frameFiles(dir).size(), refused ? 4u : 3u);
    const TextureStore reopened = TextureStore::open(dir);
    EXPECT_EQ(reopened.frameCount(kAxial), 3u);
    EXPECT_NEAR(binOneTexel(reopened), refused ? 2.0f : 4.0f, 1e-3) << refused;
  }
}

// The journal refused two runs of the slice with a kept run between them (a crash before the
// texture followed): settling sets aside the refused runs' frames alone.
TEST(TextureStore, SettlingSetsAsideTheRefusedRunsFramesAndKeepsTheRunBetween) {
  const fs::path dir = test::freshTempDir() / "texture";
  std::vector<TextureRun> refusals;
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    for (const double parameterDeg : {30.0, 60.0, 90.0}) {
      const std::uint64_t run = store.beginRun(kAxial);
      store.add(kAxial, frameAt(parameterDeg, 1.0f));
      store.add(kAxial, frameAt(parameterDeg + 1.0, 1.0f));
      store.keepRun(kAxial);
      if (parameterDeg != 60.0) refusals.push_back({kAxial, run, store.nextSequence()});
    }
  }
  TextureStore store = TextureStore::open(dir);
  EXPECT_EQ(store.settleRuns(refusals), 4u);
  EXPECT_EQ(store.frameCount(kAxial), 2u);
  EXPECT_EQ(store.filledBins(kAxial), 1);
  EXPECT_TRUE(store.wouldKeep(kAxial, 30.0));
  EXPECT_EQ(TextureStore::open(dir).frameCount(kAxial), 2u);
}

// A store opened after a refusal (a sweep again, a daemon restart) numbers its frames on from the
// set-aside ones: a later run's frame never takes their names, and a second refusal of the same
// bins keeps both runs' frames.
TEST(TextureStore, FramesAfterARefusalNeverTakeTheSetAsideFramesNames) {
  const fs::path dir = test::freshTempDir() / "texture";
  const fs::path setAside = dir / (std::string("axial-30-75") + io::kSetAsideSuffix);
  {
    TextureStore store = TextureStore::openOrCreate(dir, kLayout);
    const std::uint64_t run = store.nextSequence();
    store.add(kAxial, frameAt(1.0, 2.0f));
    store.add(kAxial, frameAt(30.0, 4.0f));
    ASSERT_EQ(store.setAside(kAxial, run), 2u);
  }
  TextureStore again = TextureStore::openOrCreate(dir, kLayout);
  const std::uint64_t run = again.nextSequence();
  EXPECT_GE(run, 2u) << "the set-aside frames' sequence numbers are taken";
  again.add(kAxial, frameAt(1.0, 2.0f));
  again.add(kAxial, frameAt(30.0, 4.0f));
  ASSERT_EQ(again.setAside(kAxial, run), 2u);
  EXPECT_EQ(frameFiles(setAside).size(), 4u) << "both refused runs' frames kept";
}

// The daemon's path (frames from a camera through makeFramePipeline's observer into a
// TextureSweep, stored per bin on disk) gives the texture `slicecap btf --ambient previous` gives
// from the same frames: the live room-light term, the same rectification and bins.
TEST(TextureSweep, TheLiveTextureIsTheOfflineOneWithTheLiveRoomLight) {
  const SliceId slice{SliceKind::Diagonal, {30, 30}};
  const fs::path recording = test::freshTempDir() / folderName(slice);
  sim::SweepSetup setup;
  setup.rig = sim::RigParams::realistic();  // 8-bit sRGB, room light, LED alternating, jitter
  setup.rig.framesPerSlice = 24;
  setup.materialSpec = "woven";
  const sim::FrameRenderer renderer(setup.camera, setup.target, sim::makeWovenMaterial(10.0),
                                    setup.rig);
  sim::simulateSweep(recording, {slice, kAxialOffsetDeg}, renderer, setup);
  constexpr int kResolution = 8, kFramesPerBin = 64;  // every frame kept: the bins must match

  capture::PipelineSettings live;
  live.offlineTwoSidedAmbient = false;
  const SessionTexture offline =
      captureRecordings({recording}, live, {kResolution, kFramesPerBin, {}});

  const fs::path storeDir = recording.parent_path() / "texture";
  TextureSweep sweep(storeDir, slice, setup.camera,
                     {kResolution, setup.target.window, kFramesPerBin});
  int stored = 0;
  const capture::FrameProcessor processor = capture::makeFramePipeline(
      setup.target, setup.camera, {},
      [&](const hal::Frame& frame, const capture::FrameOutcome& outcome,
          const std::vector<capture::AmbientTerm>& ambient) {
        stored += sweep.add(frame, outcome, ambient) ? 1 : 0;
      });
  hal::SteadyClock clock;
  hal::FileCamera camera(recording, clock);
  hal::CameraConfig config;
  config.widthPx = setup.camera.intrinsics.widthPx;
  config.heightPx = setup.camera.intrinsics.heightPx;
  camera.configure(config);
  camera.start();
  for (;;) {
    hal::CaptureResult result = camera.nextFrame(std::chrono::milliseconds(100));
    if (result.status != hal::CaptureResult::Status::Frame) break;
    processor(*result.frame, slice);
  }
  camera.stop();
  ASSERT_GE(stored, 6);
  EXPECT_EQ(TextureStore::open(storeDir).frameCount(), std::size_t(stored));

  const std::vector<SliceTexture> liveSlices = TextureStore::open(storeDir).combine();
  ASSERT_EQ(liveSlices.size(), 1u);
  ASSERT_EQ(offline.texture.slices().size(), 1u);
  const SliceTexture& want = offline.texture.slices()[0];
  int comparedBins = 0;
  for (std::size_t b = 0; b < want.bins.size(); ++b) {
    const TextureBin& a = liveSlices[0].bins[b];
    const TextureBin& w = want.bins[b];
    // Live rejects LED-on frames before the first LED-off one; offline borrows that one.
    if (a.frames != w.frames || a.frames == 0) continue;
    ++comparedBins;
    EXPECT_TRUE(a.cameraMm.isApprox(w.cameraMm, 1e-9)) << "bin " << b;
    EXPECT_TRUE(a.lightMm.isApprox(w.lightMm, 1e-9)) << "bin " << b;
    for (std::size_t i = 0; i < w.texels.size(); ++i) {
      if (std::isnan(w.texels[i])) {
        EXPECT_TRUE(std::isnan(a.texels[i])) << "bin " << b << " value " << i;
      } else {
        EXPECT_NEAR(a.texels[i], w.texels[i], 1e-3 * std::abs(w.texels[i]) + 1e-6)
            << "bin " << b << " value " << i;  // half floats on disk
      }
    }
  }
  EXPECT_GE(comparedBins, 5);
}

}  // namespace
}  // namespace slicecap::btf
