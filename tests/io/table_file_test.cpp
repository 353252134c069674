// Raw .f32 tables and the extension-based reader.
#include "slicecap/io/table_file.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "../support/test_support.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/io_error.hpp"

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

}  // namespace
}  // namespace slicecap::io
