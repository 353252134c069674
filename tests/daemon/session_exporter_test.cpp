// The session exporter: the reply lists exactly the texture files a copy needs (no temporaries,
// no discarded sweeps), the texture is skipped while a sweep captures into it, and the reply's
// files are the ones written.
#include "slicecap/daemon/session_exporter.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "../support/test_support.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::daemon {
namespace {

namespace fs = std::filesystem;

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
  const SessionExporter exporter(grayTable);
  const control::ExportView reply =
      exporter.exportSession(store, dir / "out", std::string("b"), {});
  ASSERT_EQ(reply.texture, texture.string());
  EXPECT_EQ(reply.textureFiles,
            (std::vector<std::string>{"axial-30-30/0001.tex", "slices.csv", "texture.json"}));
  EXPECT_FALSE(reply.textureSkipped);
  for (const std::string& file : reply.files) EXPECT_TRUE(fs::is_regular_file(file)) << file;
  EXPECT_TRUE(fs::exists(dir / "out" / "felt-abrdf-b.exr"));
  EXPECT_EQ(reply.method, "b");
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

}  // namespace
}  // namespace slicecap::daemon
