// ABRDF EXR: exact round trips, header attributes, and rejection of anything else.
#include "slicecap/io/abrdf_exr.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

Abrdf rampTable() {
  Abrdf t;
  for (std::size_t i = 0; i < t.values().size(); ++i)
    t.values()[i] = float(i) * 1e-3f + 1e-7f;
  return t;
}

// Writes an EXR of any size and channel set, for the rejection tests.
void writeRawExr(const std::filesystem::path& path, int width, int height,
                 const std::vector<std::string>& channels,
                 const std::map<std::string, std::string>& attributes) {
  Imf::Header header(width, height);
  for (const std::string& c : channels)
    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  for (const auto& [k, v] : attributes)
    header.insert(k, Imf::StringAttribute(v));
  std::vector<float> pixels(std::size_t(width) * height, 0.5f);
  Imf::FrameBuffer frame;
  for (const std::string& c : channels) {
    frame.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data()), sizeof(float),
                               sizeof(float) * width));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(height);
}

std::string readError(const std::filesystem::path& path) {
  try {
    readAbrdfExr(path);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

const std::map<std::string, std::string> kGoodAttributes{{"slicecap:layout", "bonn81"},
                                                         {"slicecap:quantity", "brdf"}};

TEST(AbrdfExr, RoundTripsValuesAndAttributesExactly) {
  const auto dir = test::freshTempDir();
  const Abrdf table = rampTable();
  writeAbrdfExr(dir / "t.exr", table, {{"method", "B"}, {"material", "felt"}});
  ExrAttributes attributes;
  const Abrdf back = readAbrdfExr(dir / "t.exr", &attributes);
  EXPECT_EQ(back, table);
  EXPECT_EQ(attributes.at("layout"), "bonn81");
  EXPECT_EQ(attributes.at("quantity"), "brdf");
  EXPECT_EQ(attributes.at("method"), "B");
  EXPECT_EQ(attributes.at("material"), "felt");
  EXPECT_FALSE(attributes.at("version").empty());
}

TEST(AbrdfExr, RowsAreLightsAndColumnsAreViews) {
  const auto dir = test::freshTempDir();
  Abrdf table;
  table.set(2, 8, {1, 2, 3});
  writeAbrdfExr(dir / "t.exr", table);
  Imf::InputFile file((dir / "t.exr").c_str());
  std::vector<float> red(81 * 81);
  Imf::FrameBuffer frame;
  frame.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(red.data()), sizeof(float),
                               sizeof(float) * 81));
  file.setFrameBuffer(frame);
  file.readPixels(0, 80);
  EXPECT_EQ(red[2 * 81 + 8], 1.0f) << "row 2 (light), column 8 (view)";
  EXPECT_EQ(red[8 * 81 + 2], 0.0f);
}

TEST(AbrdfExr, RejectsAWrongSize) {
  const auto dir = test::freshTempDir();
  writeRawExr(dir / "small.exr", 81, 80, {"R", "G", "B"}, kGoodAttributes);
  const std::string error = readError(dir / "small.exr");
  EXPECT_NE(error.find("small.exr"), std::string::npos) << error;
  EXPECT_NE(error.find("81 x 81"), std::string::npos) << error;
}

TEST(AbrdfExr, RejectsAMissingChannel) {
  const auto dir = test::freshTempDir();
  writeRawExr(dir / "rg.exr", 81, 81, {"R", "G"}, kGoodAttributes);
  const std::string error = readError(dir / "rg.exr");
  EXPECT_NE(error.find("rg.exr"), std::string::npos) << error;
  EXPECT_NE(error.find("channel B"), std::string::npos) << error;
}

TEST(AbrdfExr, RejectsAnotherLayoutOrNoLayout) {
  const auto dir = test::freshTempDir();
  writeRawExr(dir / "utia.exr", 81, 81, {"R", "G", "B"},
              {{"slicecap:layout", "utia"}, {"slicecap:quantity", "brdf"}});
  EXPECT_NE(readError(dir / "utia.exr").find("slicecap:layout is \"utia\""), std::string::npos);
  writeRawExr(dir / "plain.exr", 81, 81, {"R", "G", "B"}, {});
  EXPECT_NE(readError(dir / "plain.exr").find("missing header attribute slicecap:layout"),
            std::string::npos);
  writeRawExr(dir / "abrdf.exr", 81, 81, {"R", "G", "B"},
              {{"slicecap:layout", "bonn81"}, {"slicecap:quantity", "abrdf"}});
  EXPECT_NE(readError(dir / "abrdf.exr").find("quantity"), std::string::npos);
}

// A table written past writeAbrdfExr, which refuses the values these tests put in.
void writeTableRaw(const std::filesystem::path& path, Abrdf table) {
  Imf::Header header(Abrdf::kDirections, Abrdf::kDirections);
  for (const char* c : {"R", "G", "B"})
    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  for (const auto& [k, v] : kGoodAttributes)
    header.insert(k, Imf::StringAttribute(v));
  Imf::FrameBuffer frame;
  for (int c = 0; c < 3; ++c)
    frame.insert(std::string(1, "RGB"[c]),
                 Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(table.values().data() + c),
                            3 * sizeof(float), 3 * sizeof(float) * Abrdf::kDirections));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(Abrdf::kDirections);
}

TEST(AbrdfExr, RejectsNonFiniteValues) {
  const auto dir = test::freshTempDir();
  Abrdf table;
  table.channel(5, 6, 2) = std::numeric_limits<float>::quiet_NaN();
  writeTableRaw(dir / "nan.exr", table);
  const std::string error = readError(dir / "nan.exr");
  EXPECT_NE(error.find("non-finite value at light 5, view 6, channel B"), std::string::npos)
      << error;
}

TEST(AbrdfExr, RejectsNegativeValuesButReadsNegativeZero) {
  // A BRDF is never negative and no reconstruction writes one; a table from another tool that
  // holds one would render as negative light on the desktop.
  const auto dir = test::freshTempDir();
  Abrdf table = rampTable();
  table.channel(2, 9, 0) = -0.0f;
  writeTableRaw(dir / "zero.exr", table);
  EXPECT_EQ(readAbrdfExr(dir / "zero.exr"), table);
  table.channel(4, 11, 1) = -0.25f;
  writeTableRaw(dir / "negative.exr", table);
  const std::string error = readError(dir / "negative.exr");
  EXPECT_NE(error.find((dir / "negative.exr").string() +
                       ": negative value -0.25 at light 4, view 11, channel G"),
            std::string::npos)
      << error;
}

TEST(AbrdfExr, RefusesToWriteNonFiniteOrNegativeValuesNamingTheFirst) {
  // `reconstruct` wrote an EXR holding inf (from one sample of 1e35) that its own reader refused.
  const auto dir = test::freshTempDir();
  writeAbrdfExr(dir / "t.exr", rampTable());
  for (const float bad :
       {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(), -1e-6f}) {
    Abrdf table = rampTable();
    table.channel(7, 3, 1) = bad;
    table.channel(9, 0, 0) = bad;
    try {
      writeAbrdfExr(dir / "t.exr", table);
      ADD_FAILURE() << bad << " was written";
    } catch (const IoError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find((dir / "t.exr").string() + ": not written: a "), std::string::npos)
          << message;
      EXPECT_NE(message.find("light 7, view 3, channel G"), std::string::npos) << message;
    }
    EXPECT_EQ(readAbrdfExr(dir / "t.exr"), rampTable()) << "the old file is kept";
  }
}

TEST(AbrdfExr, RejectsMissingAndCorruptFiles) {
  const auto dir = test::freshTempDir();
  EXPECT_NE(readError(dir / "none.exr").find("none.exr"), std::string::npos);
  std::ofstream(dir / "junk.exr") << "this is not an EXR file";
  EXPECT_NE(readError(dir / "junk.exr").find("junk.exr"), std::string::npos);
  // A valid file cut in half.
  writeAbrdfExr(dir / "whole.exr", rampTable());
  const auto size = std::filesystem::file_size(dir / "whole.exr");
  std::filesystem::copy_file(dir / "whole.exr", dir / "cut.exr");
  std::filesystem::resize_file(dir / "cut.exr", size / 2);
  EXPECT_NE(readError(dir / "cut.exr").find("cut.exr"), std::string::npos);
  EXPECT_THROW(writeAbrdfExr(dir / "no" / "such" / "dir.exr", rampTable()), IoError);
}

}  // namespace
}  // namespace slicecap::io
