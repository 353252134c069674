// The session exporter: one set, replaced as a whole. The reply lists exactly the texture files a
// copy needs (no temporaries, no discarded sweeps), the texture is skipped while a sweep captures
// into it, and the reply's files are the ones written; through the session manager's export, a
// full disk leaves the folder's earlier export whole, a link planted in the folder is never
// written through, only files the export wrote are removed, and what a damaged journal set aside
// goes with it.
#include "slicecap/daemon/session_exporter.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>

#include "../support/manager_reply.hpp"
#include "../support/small_disk.hpp"
#include "../support/test_support.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::daemon {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};

Abrdf grayTable(const SliceSet&, const std::string&) {
  Abrdf table;
  for (int light = 0; light < bonn::kDirectionCount; ++light)
    for (int view = 0; view < bonn::kDirectionCount; ++view)
      table.set(light, view, Rgb::gray(0.5f));
  return table;
}

capture::SessionStore sweptSession(const fs::path& root) {
  capture::SessionStore store = capture::SessionStore::create(root, "felt", "felt");
  store.recordSweepStarted(kAxial3030);
  for (std::uint64_t k = 0; k < 24; ++k)
    store.recordSample(kAxial3030, {std::int64_t(k) * 33000,
                                    k,
                                    {30, double(k) * 15.0},
                                    {30, double(k) * 15.0 + 15},
                                    Rgb::gray(0.5)});
  store.recordSweepStopped(kAxial3030);
  return store;
}

void touch(const fs::path& path) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << "frame";
}

TEST(SessionExporter, ListsTheTextureFilesACopyNeeds) {
  const auto dir = test::freshTempDir();
  const capture::SessionStore store = sweptSession(dir / "storage");
  const fs::path texture = store.directory() / kTextureFolder;
  touch(texture / "texture.json");
  touch(texture / "axial-30-30" / "0001.tex");
  touch(texture / "axial-30-30" / "0002.tex.tmp");  // a frame being written
  touch(texture / (std::string("axial-75-75") + io::kDiscardedSuffix) / "0001.tex");
  // A refused run's frames, set aside beside the slice's frames of its other runs.
  touch(texture / (std::string("axial-30-30") + io::kSetAsideSuffix) / "b00-00000003.tex");
  touch(texture / (std::string("axial-30-30") + io::kSetAsideSuffix) / "b02-00000004.tex");
  // A frame of an earlier run an unjudged run replaced: no longer the texture's, not copied.
  touch(texture / (std::string("axial-30-30") + io::kHeldSuffix) / "00000005" / "b00-00000001.tex");
  const SessionExporter exporter(grayTable);
  const control::ExportView reply =
      exporter.exportSession(store, dir / "out", std::string("b"), {});
  ASSERT_EQ(reply.texture, texture.string());
  EXPECT_EQ(reply.textureFiles,
            (std::vector<std::string>{"axial-30-30/0001.tex", "slices.csv", "texture.json"}));
  EXPECT_TRUE(std::any_of(reply.warnings.begin(), reply.warnings.end(), [](const std::string& w) {
    return w.find("texture: 2 frames of refused sweep runs left out (kept in "
                  "texture/axial-30-30.set-aside)") != std::string::npos;
  })) << testing::PrintToString(reply.warnings);
  EXPECT_FALSE(reply.textureSkipped);
  for (const std::string& file : reply.files) EXPECT_TRUE(fs::is_regular_file(file)) << file;
  EXPECT_TRUE(fs::exists(dir / "out" / "felt-abrdf-b.exr"));
  EXPECT_EQ(reply.method, "b");
}

// Method B with every slice; while a slice is missing, the prior fitted to every window cell (a
// slice set without cells is read at its window centres by the same method, so the default
// depends only on which slices have samples).
TEST(SessionExporter, DefaultsToMethodBElseThePriorOnEveryCell) {
  SliceSet every, allButOne;
  for (const SliceId& slice : sweepOrder()) {
    const SliceSample sample{{double(slice.elevations.thetaIDeg), 0.0},
                             {double(slice.elevations.thetaVDeg), 180.0},
                             Rgb::gray(0.5)};
    every.add(slice, sample);
    if (slice != kAxial3030) allButOne.add(slice, sample);
  }
  EXPECT_EQ(defaultExportMethod(every), "b");
  EXPECT_EQ(defaultExportMethod(allButOne), "prior-cells");
}

// A method that fails names the prior of its own reading, which reads any subset of the slices.
TEST(SessionExporter, AFailedMethodNamesThePriorOfItsOwnReading) {
  const auto dir = test::freshTempDir();
  const capture::SessionStore store = sweptSession(dir / "storage");
  const SessionExporter exporter([](const SliceSet&, const std::string&) -> Abrdf {
    throw std::runtime_error("missing slices: diagonal 75/75");
  });
  const SliceSet slices = store.slices();
  auto messageOf = [&](const std::string& method) {
    try {
      exporter.reconstruct(store, slices, method);
    } catch (const RequestError& refusal) {
      return std::string(refusal.what());
    }
    ADD_FAILURE() << method << " did not fail";
    return std::string();
  };
  EXPECT_THAT(messageOf("b-cells"), HasSubstr("(`--method prior-cells` reconstructs from any subset"));
  EXPECT_THAT(messageOf("b"), HasSubstr("(`--method prior` reconstructs from any subset"));
  EXPECT_THAT(messageOf("prior-cells"), ::testing::Not(HasSubstr("--method prior")));
  EXPECT_THAT(messageOf("prior"), ::testing::Not(HasSubstr("--method prior")));
}

TEST(SessionExporter, SkipsTheTextureWhileASweepCapturesIntoIt) {
  const auto dir = test::freshTempDir();
  const capture::SessionStore store = sweptSession(dir / "storage");
  touch(store.directory() / kTextureFolder / "texture.json");
  const SessionExporter exporter(grayTable);
  const control::ExportView reply =
      exporter.exportSession(store, dir / "out", std::string("b"), {kAxial3030, true});
  EXPECT_FALSE(reply.texture);
  EXPECT_TRUE(reply.textureFiles.empty());
  ASSERT_TRUE(reply.textureSkipped);
  EXPECT_NE(reply.textureSkipped->find("axial 30/30"), std::string::npos) << *reply.textureSkipped;
}

std::array<double, 3> pointAt(const Direction& d, double distanceMm) {
  const UnitVector u = toUnitVector(d);
  return {distanceMm * u.x, distanceMm * u.y, distanceMm * u.z};
}

TEST(SessionExporter, TheSummarySaysHowEachSlicesCellsWereRead) {
  // A plain material under a print: the window's four cells read 1.6, 1, 1, 0.4 x the same
  // value in every frame, the texture the export's reading judges.
  const auto dir = test::freshTempDir();
  capture::SessionStore store = capture::SessionStore::create(dir / "storage", "felt", "felt");
  store.recordSweepStarted(kAxial3030);
  const std::array<double, 4> print{1.6, 1.0, 1.0, 0.4};
  for (std::uint64_t k = 0; k < 24; ++k) {
    const Direction light{30, double(k) * 15.0}, view{30, double(k) * 15.0 + 180};
    capture::FrameSample sample{std::int64_t(k) * 33000, k, light, view, Rgb::gray(0.5)};
    capture::WindowCells cells;
    cells.cellsPerSide = 2;
    cells.gridMm = {-20, -20, 20, 20};
    cells.lightMm = pointAt(light, 300);
    cells.cameraMm = pointAt(view, 300);
    cells.cells.resize(4);
    capture::placeCellDirections(cells);
    for (std::size_t c = 0; c < 4; ++c) {
      cells.cells[c].value = Rgb::gray(0.5 * print[c]);
      cells.cells[c].variance = Rgb::gray(1e-6);
    }
    sample.cells = std::move(cells);
    store.recordSample(kAxial3030, sample);
  }
  store.recordSweepStopped(kAxial3030);
  const SessionExporter exporter(grayTable);
  exporter.exportSession(store, dir / "out", std::string("b"), {});
  std::ifstream file(dir / "out" / "felt-summary.json");
  const json summary = json::parse(file);
  const capture::CellTexture judged = capture::cellTextureOf(store.bins(kAxial3030));
  EXPECT_NE(judged.action, capture::CellTextureAction::AsRead) << judged.describe();
  ASSERT_TRUE(summary.contains("cell_texture")) << summary.dump(2);
  const json& verdict = summary["cell_texture"][toString(kAxial3030)];
  EXPECT_EQ(verdict["action"], std::string(capture::toString(judged.action)));
  EXPECT_EQ(verdict["summary"], judged.describe());
  // A slice without cells has no verdict to report.
  const json plain = [&] {
    const capture::SessionStore other = sweptSession(dir / "plain");
    exporter.exportSession(other, dir / "plain-out", std::string("b"), {});
    std::ifstream plainFile(dir / "plain-out" / "felt-summary.json");
    return json::parse(plainFile);
  }();
  EXPECT_EQ(plain["cell_texture"], json::object());
}

// A table of the mean sample value: a new sweep changes every byte of it.
Abrdf meanTable(const SliceSet& slices, const std::string&) {
  double sum = 0;
  for (const Slice& slice : slices.slices())
    for (const SliceSample& sample : slice.samples)
      sum += sample.value.r();
  Abrdf table;
  for (int light = 0; light < bonn::kDirectionCount; ++light)
    for (int view = 0; view < bonn::kDirectionCount; ++view)
      table.set(light, view, Rgb::gray(static_cast<float>(sum / double(slices.sampleCount()))));
  return table;
}

// A preview as big as a real PNG can be, bigger for a brighter table (so a new export needs more
// room than the one it replaces), failing as the real one does when the disk is full.
void bigPreview(const Abrdf& table, const fs::path& png) {
  std::ofstream out(png, std::ios::binary);
  out << std::string(100000 + std::size_t(table.at(0, 0).r() * 400000), 'p');
  out.close();
  if (!out) throw io::IoError(png.string() + ": write failed");
}

// Each file's name with its size and a hash of its bytes (short enough to print when they differ).
std::map<std::string, std::string> snapshot(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes =
        entry.is_regular_file() ? std::string(std::istreambuf_iterator<char>(in), {}) : "";
    files[fs::relative(entry.path(), folder).string()] =
        std::to_string(bytes.size()) + " bytes, hash " +
        std::to_string(std::hash<std::string>{}(bytes));
  }
  return files;
}

using test::ok;

void sweep(SessionManager& manager, double value, std::uint64_t firstFrame) {
  ok(manager, control::SweepStart{kAxial3030});
  for (std::uint64_t k = 0; k < 24; ++k)
    ASSERT_TRUE(manager.acceptSample({std::int64_t(firstFrame + k) * 33000,
                                      firstFrame + k,
                                      {30, double(k) * 15.0},
                                      {30, double(k) * 15.0 + 15},
                                      Rgb::gray(value)}));
  ok(manager, control::SweepStop{});
}

TEST(SessionExport, AFullDiskLeavesTheEarlierExportWhole) {
  const auto dir = test::freshTempDir();
  test::SmallDisk disk(dir / "small", "1M");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a small tmpfs here (" << disk.why() << ")";
  const fs::path out = dir / "small" / "out";
  SessionManager manager(dir / "storage", meanTable, bigPreview);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  sweep(manager, 0.25, 0);
  ok(manager, control::Export{std::nullopt, out.string(), std::string("b")});
  const auto before = snapshot(out);
  sweep(manager, 0.75, 100);
  disk.fill(dir / "small" / "filler", 50000);
  auto reply = manager.handle(control::Export{std::nullopt, out.string(), std::string("b")});
  ASSERT_TRUE(std::holds_alternative<control::ProtocolError>(reply)) << "the export did not fail";
  EXPECT_EQ(std::get<control::ProtocolError>(reply).code, control::ErrorCode::StorageError);
  EXPECT_EQ(snapshot(out), before) << "the folder holds neither the old export nor the new one";
  // With room again, the new export goes in whole.
  fs::remove(dir / "small" / "filler");
  ok(manager, control::Export{std::nullopt, out.string(), std::string("b")});
  EXPECT_NE(snapshot(out), before);
}

TEST(SessionExport, ALinkPlantedInTheFolderIsReplacedAndForeignTablesStay) {
  const auto dir = test::freshTempDir();
  const fs::path out = dir / "out";
  fs::create_directories(out);
  std::ofstream(dir / "victim") << "not the daemon's";
  fs::create_symlink(dir / "victim", out / "felt-summary.json");
  fs::create_symlink(dir / "victim", out / "felt-slices.csv");
  std::ofstream(out / "felt-abrdf-mine.exr") << "the person's own table";
  SessionManager manager(dir / "storage", meanTable);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  sweep(manager, 0.25, 0);
  ok(manager, control::Export{std::nullopt, out.string(), std::string("b")});
  std::ifstream victim(dir / "victim");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(victim), {}), "not the daemon's");
  EXPECT_FALSE(fs::is_symlink(out / "felt-summary.json"));
  EXPECT_FALSE(fs::is_symlink(out / "felt-slices.csv"));
  EXPECT_TRUE(fs::exists(out / "felt-abrdf-mine.exr")) << "the export did not write it";
}

// A material function as slicecapd's is, but cheap: one file holding the table's first value.
ExportedMaterial oneFileMaterial(const Abrdf& table, const std::string& tableName) {
  const float value = table.at(0, 0).r();
  return {{{"-material.json",
            [value, tableName](const fs::path& path) {
              std::ofstream(path) << "{\"source\": \"" << tableName << "\", \"value\": " << value << "}";
            }}},
          "fitted from " + tableName};
}

TEST(SessionExport, HoldsTheFirstTablesFittedMaterialExceptWhileASweepRuns) {
  const auto dir = test::freshTempDir();
  const fs::path out = dir / "out";
  SessionManager manager(dir / "storage", meanTable, {}, {}, oneFileMaterial);
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  sweep(manager, 0.25, 0);
  const json reply = ok(manager, control::Export{std::nullopt, out.string(), std::string("b")});
  EXPECT_EQ(reply["material"], "fitted from felt-abrdf-b.exr");
  ASSERT_TRUE(fs::exists(out / "felt-material.json"));
  EXPECT_THAT(reply["files"].dump(), HasSubstr("felt-material.json"));
  std::ifstream written(out / "felt-material.json");
  EXPECT_THAT(std::string(std::istreambuf_iterator<char>(written), {}), HasSubstr("0.25"));

  // While a sweep runs, no fit (it would hold up the frames): said, and the earlier file goes as
  // a stale member of the set rather than stay beside newer tables.
  ok(manager, control::SweepStart{kAxial3030});
  const json during = ok(manager, control::Export{std::nullopt, out.string(), std::string("b")});
  EXPECT_THAT(during["material"].get<std::string>(), HasSubstr("not fitted while sweep"));
  EXPECT_FALSE(fs::exists(out / "felt-material.json"));
}

TEST(SessionExport, ATableThatCannotBeFittedIsAWarningNotAFailedExport) {
  const auto dir = test::freshTempDir();
  const fs::path out = dir / "out";
  SessionManager manager(dir / "storage", meanTable, {}, {},
                         [](const Abrdf&, const std::string& name) -> ExportedMaterial {
                           throw std::runtime_error(name + ": the fit did not converge");
                         });
  ok(manager, control::SessionNew{"felt", std::string("felt")});
  sweep(manager, 0.25, 0);
  const json reply = ok(manager, control::Export{std::nullopt, out.string(), std::string("b")});
  EXPECT_TRUE(fs::exists(out / "felt-abrdf-b.exr"));
  EXPECT_FALSE(fs::exists(out / "felt-material.json"));
  EXPECT_THAT(reply["warnings"].dump(), HasSubstr("no fitted material: felt-abrdf-b.exr: the fit did not converge"));
}

TEST(SessionExport, WhatADamagedJournalSetAsideIsSaidWithTheExport) {
  const auto dir = test::freshTempDir();
  {
    SessionManager manager(dir / "storage", meanTable);
    ok(manager, control::SessionNew{"felt", std::string("felt")});
    sweep(manager, 0.25, 0);
    ok(manager, control::SweepRedo{kAxial3030});
    ok(manager, control::SweepStop{});
  }
  // One flipped byte in the redo record.
  const fs::path journal = dir / "storage" / "felt" / "journal";
  std::string bytes;
  {
    std::ifstream in(journal, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.find("\"redo\"") + 2] = 'x';
  std::ofstream(journal, std::ios::binary | std::ios::trunc) << bytes;

  SessionManager manager(dir / "storage", meanTable);
  const json shown = ok(manager, control::SessionShow{"felt"});
  EXPECT_EQ(shown["samples"], 0) << "the redone sweep's samples came back";
  ASSERT_TRUE(shown.contains("journal_damage"));
  EXPECT_THAT(shown["journal_damage"][0]["message"].get<std::string>(),
              HasSubstr(journal.string() + " line "));
  EXPECT_EQ(shown["slices"][4]["samples_set_aside"], 24);
  EXPECT_TRUE(manager.status()["session"].contains("journal_damage"));
}

}  // namespace
}  // namespace slicecap::daemon
