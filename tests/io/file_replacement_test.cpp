// Every file writer of lib/io goes through a temporary: a write that fails half-way (an exception,
// a full disk) leaves the old file as it was and no temporary behind.
#include "slicecap/io/file_replacement.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include "../support/file_size_limit.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/io/target_print.hpp"

namespace slicecap::io {
namespace {

namespace fs = std::filesystem;

std::string contentsOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The names in `dir`, to see that no temporary is left.
std::vector<std::string> namesIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(FileReplacement, AWriterThatThrowsHalfWayLeavesTheOldFileAndNoTemporary) {
  const fs::path dir = test::freshTempDir();
  const fs::path target = dir / "table.csv";
  std::ofstream(target) << "the old contents\n";
  EXPECT_THROW(writeStreamReplacing(target,
                                    [](std::ostream& out) {
                                      out << "half of the new";
                                      throw std::runtime_error("the writer failed");
                                    }),
               std::runtime_error);
  EXPECT_EQ(contentsOf(target), "the old contents\n");
  EXPECT_EQ(namesIn(dir), std::vector<std::string>{"table.csv"});

  writeStreamReplacing(target, [](std::ostream& out) { out << "new\n"; });
  EXPECT_EQ(contentsOf(target), "new\n");
  EXPECT_EQ(namesIn(dir), std::vector<std::string>{"table.csv"});
}

TEST(FileReplacement, AFullDiskIsAnErrorNamingTheTargetAndCostsNothing) {
  const fs::path dir = test::freshTempDir();
  const fs::path target = dir / "big.bin";
  std::ofstream(target) << "old";
  try {
    const test::FileSizeLimit limit(1000);  // writes past 1000 bytes fail as on a full disk
    writeStreamReplacing(target, [](std::ostream& out) { out << std::string(5000, 'x'); });
    ADD_FAILURE() << "the failed write was not noticed";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(target.string() + ": write failed"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(contentsOf(target), "old");
  EXPECT_EQ(namesIn(dir), std::vector<std::string>{"big.bin"});
}

// Files replaced together: one that cannot be written keeps every target as it was, the ones
// written before it too, and leaves no temporary.
TEST(FileReplacement, FilesReplacedTogetherKeepAllWhenOneFails) {
  const fs::path dir = test::freshTempDir();
  std::ofstream(dir / "a.json") << "old a";
  std::ofstream(dir / "c.xml") << "old c";
  try {
    replaceFilesTogether({{dir / "a.json", "new a"},
                          {dir / "missing" / "b.gltf", "new b"},
                          {dir / "c.xml", "new c"}});
    ADD_FAILURE() << "the failed write was not noticed";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "missing" / "b.gltf").string()), std::string::npos)
        << e.what();
  }
  try {
    const test::FileSizeLimit limit(1000);  // writes past 1000 bytes fail as on a full disk
    replaceFilesTogether({{dir / "a.json", "new a"}, {dir / "c.xml", std::string(5000, 'x')}});
    ADD_FAILURE() << "the full disk was not noticed";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "c.xml").string() + ": write failed"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(contentsOf(dir / "a.json"), "old a");
  EXPECT_EQ(contentsOf(dir / "c.xml"), "old c");
  EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"a.json", "c.xml"}));

  replaceFilesTogether({{dir / "a.json", "new a"}, {dir / "c.xml", "new c"}});
  EXPECT_EQ(contentsOf(dir / "a.json"), "new a");
  EXPECT_EQ(contentsOf(dir / "c.xml"), "new c");
  EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"a.json", "c.xml"}));
}

TEST(FileReplacement, EveryWriterKeepsTheOldFileWhenTheDiskIsFull) {
  const fs::path dir = test::freshTempDir();
  // Contents that do not compress below the limit.
  Abrdf table;
  for (std::size_t i = 0; i < table.values().size(); ++i)
    table.values()[i] = static_cast<float>((i * 7919) % 1000) / 7.0f;
  SliceSet slices;
  for (int i = 0; i < 100; ++i)
    slices.add({SliceKind::Axial, {30, 30}}, {{30.0, i * 3.6}, {30.0, i * 3.6 + 15.0}, {1, 2, 3}});
  PngImage image{200, 100, 3, 16, {}};
  for (std::size_t i = 0; i < 200 * 100 * 3; ++i)
    image.samples.push_back(static_cast<std::uint16_t>((i * 40503) % 65536));
  const std::vector<std::pair<std::string, std::function<void(const fs::path&)>>> writers = {
      {"slices.csv", [&](const fs::path& p) { writeSliceCsv(p, slices); }},
      {"table.f32", [&](const fs::path& p) { writeF32Table(p, table); }},
      {"table.exr", [&](const fs::path& p) { writeAbrdfExr(p, table); }},
      {"image.png", [&](const fs::path& p) { writePng(p, image); }},
      {"target.svg", [&](const fs::path& p) { writeTargetSvg(p, vision::defaultTarget()); }},
      {"target.pdf", [&](const fs::path& p) { writeTargetPdf(p, vision::defaultTarget()); }},
  };
  for (const auto& [name, write] : writers) {
    SCOPED_TRACE(name);
    const fs::path target = dir / name;
    std::ofstream(target) << "old " << name;
    try {
      const test::FileSizeLimit limit(1000);
      write(target);
      ADD_FAILURE() << "the failed write was not noticed";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
    EXPECT_EQ(contentsOf(target), "old " + name);
    EXPECT_FALSE(fs::exists(target.string() + ".tmp"));
    write(target);  // and without the limit it is written
    EXPECT_GT(fs::file_size(target), 1000u);
  }
}

TEST(FileReplacement, ALinkStaysALinkADeviceIsWrittenInPlaceADirectoryIsNamed) {
  const fs::path dir = test::freshTempDir();
  std::ofstream(dir / "real.csv") << "old";
  fs::create_symlink("real.csv", dir / "link.csv");
  writeStreamReplacing(dir / "link.csv", [](std::ostream& out) { out << "new"; });
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(contentsOf(dir / "real.csv"), "new");
  EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"link.csv", "real.csv"}));
  // `-o /dev/null` (or /dev/stdout) cannot be replaced and need not be.
  EXPECT_NO_THROW(writeStreamReplacing("/dev/null", [](std::ostream& out) { out << "x"; }));
  try {
    writeStreamReplacing(dir, [](std::ostream& out) { out << "x"; });
    ADD_FAILURE() << "a directory was written";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.string() + ": is a directory"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace slicecap::io
