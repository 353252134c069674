// Raw .f32 tables and the extension-based reader.
#include "slicecap/io/table_file.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <fstream>
#include <functional>
#include <limits>

#include "../support/test_support.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::io {
namespace {

TEST(TableFile, F32RoundTripAndLayout) {
  const auto dir = test::freshTempDir();
  Abrdf table;
  table.set(0, 1, {1.5f, 2.5f, 3.5f});
  table.set(80, 80, {7, 8, 9});
  writeF32Table(dir / "t.f32", table);
  EXPECT_EQ(std::filesystem::file_size(dir / "t.f32"), 81u * 81u * 3u * 4u);
  EXPECT_EQ(readTable(dir / "t.f32"), table);
  // Value (light 0, view 1, G) sits at float index 4, little-endian.
  std::ifstream in(dir / "t.f32", std::ios::binary);
  in.seekg(4 * 4);
  unsigned char bytes[4];
  in.read(reinterpret_cast<char*>(bytes), 4);
  EXPECT_EQ(bytes[3], 0x40);  // 2.5f = 0x40200000
  EXPECT_EQ(bytes[2], 0x20);
}

TEST(TableFile, RejectsWrongSizesAndUnknownFormats) {
  const auto dir = test::freshTempDir();
  std::ofstream(dir / "short.f32") << "abc";
  try {
    readTable(dir / "short.f32");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("short.f32"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("has 3"), std::string::npos);
  }
  EXPECT_THROW(readTable(dir / "table.png"), IoError);
  EXPECT_THROW(readTable(dir / "absent.f32"), IoError);
  writeAbrdfExr(dir / "t.exr", Abrdf());
  EXPECT_EQ(readTable(dir / "t.exr"), Abrdf());
}

TEST(TableFile, F32RejectsNonFiniteAndNegativeValuesInBothDirections) {
  if constexpr (std::endian::native != std::endian::little)
    GTEST_SKIP() << "writes the little-endian file with the host's floats";
  const auto dir = test::freshTempDir();
  Abrdf good;
  good.set(3, 4, {0.5f, 0.25f, 0.125f});
  writeF32Table(dir / "t.f32", good);
  for (const auto& [bad, said] :
       {std::pair{-0.5f, std::string("negative value -0.5 at light 3, view 4, channel G")},
        std::pair{std::numeric_limits<float>::infinity(),
                  std::string("non-finite value at light 3, view 4, channel G")}}) {
    SCOPED_TRACE(said);
    Abrdf table = good;
    table.channel(3, 4, 1) = bad;
    try {
      writeF32Table(dir / "t.f32", table);
      ADD_FAILURE() << "written";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find((dir / "t.f32").string() + ": not written: a " + said),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(readF32Table(dir / "t.f32"), good) << "the old file is kept";
    // The same value written past the writer, as another tool might.
    {
      std::ofstream file(dir / "other.f32", std::ios::binary);
      for (float v : table.values())
        file.write(reinterpret_cast<const char*>(&v), sizeof v);
    }
    try {
      readF32Table(dir / "other.f32");
      ADD_FAILURE() << "read";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find((dir / "other.f32").string() + ": " + said),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(TableFile, EveryReaderNamesADirectoryGivenForAFile) {
  // They said "basic_filebuf::underflow error reading the file: Is a directory" or "read error",
  // naming no path.
  const auto dir = test::freshTempDir();
  const std::vector<std::pair<std::string, std::function<void(const std::filesystem::path&)>>>
      readers = {{"t.f32", [](const auto& p) { readF32Table(p); }},
                 {"t.exr", [](const auto& p) { readAbrdfExr(p); }},
                 {"any", [](const auto& p) { readTable(p); }},
                 {"s.csv", [](const auto& p) { readSliceCsv(p); }},
                 {"f.png", [](const auto& p) { readPng(p); }},
                 {"c.json", [](const auto& p) { readJsonFile(p); }},
                 {"target.json", [](const auto& p) { readTargetJson(p); }}};
  for (const auto& [name, read] : readers) {
    SCOPED_TRACE(name);
    const auto path = dir / name;
    std::filesystem::create_directories(path);
    try {
      read(path);
      ADD_FAILURE() << "a directory was read";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ": is a directory"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace slicecap::io
