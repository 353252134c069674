// The BTF building blocks: texel geometry, bounded texture bins with per-texel medians, half-float
// storage, and the directory's round trip and naming.
#include "slicecap/btf/btf_texture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "../support/file_size_limit.hpp"
#include "../support/test_support.hpp"
#include "slicecap/btf/btf_error.hpp"
#include "slicecap/btf/btf_files.hpp"
#include "slicecap/btf/slice_texture.hpp"
#include "slicecap/btf/texture_grid.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::btf {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(TextureGrid, TexelsTileTheWindowRowZeroAtTheTop) {
  const TextureGrid grid(4, {-20.0, -10.0, 20.0, 10.0});
  EXPECT_DOUBLE_EQ(grid.texelWidthMm(), 10.0);
  EXPECT_DOUBLE_EQ(grid.texelHeightMm(), 5.0);
  EXPECT_EQ(grid.texelCentreMm(0, 0), Eigen::Vector3d(-15.0, 7.5, 0.0));
  EXPECT_EQ(grid.texelCentreMm(3, 3), Eigen::Vector3d(15.0, -7.5, 0.0));
  EXPECT_EQ(grid.pointMm(4, 4), Eigen::Vector3d(20.0, -10.0, 0.0));
  EXPECT_EQ(grid.index(1, 2), 9u);
  EXPECT_THROW(TextureGrid(0, {-1, -1, 1, 1}), btf::BtfError);
  EXPECT_THROW(TextureGrid(8, {1, -1, 1, 1}), btf::BtfError);
}

TextureFrame frameAt(double parameterDeg, float value, std::size_t texels = 2) {
  return {
      parameterDeg, {0.0, 0.0, 300.0}, {0.0, 100.0, 280.0}, std::vector<float>(texels * 3, value)};
}

TEST(SliceTextureBins, KeepsTheFramesNearestTheBinCentreAndTheirPerTexelMedian) {
  SliceTextureBins bins({SliceKind::Axial, {30, 30}}, 2, 3);
  // Bin 2 spans 22.5 .. 37.5 deg around 30: five frames, the three nearest 30 are kept.
  for (const auto& [parameter, value] : std::vector<std::pair<double, float>>{
           {23.0, 100.f}, {29.0, 1.f}, {36.0, 50.f}, {31.0, 3.f}, {30.5, 2.f}})
    bins.add(frameAt(parameter, value));
  bins.add(frameAt(359.0, 7.f));  // bin 0 wraps around 0
  EXPECT_EQ(bins.filledCount(), 2);
  EXPECT_EQ(bins.memoryBytes(), 4u * 2 * 3 * sizeof(float));
  const SliceTexture texture = bins.combine();
  ASSERT_EQ(texture.bins.size(), 24u);
  EXPECT_EQ(texture.bins[2].frames, 3);
  EXPECT_FLOAT_EQ(texture.bins[2].texels[0], 2.f);  // median of 1, 3, 2
  EXPECT_EQ(texture.bins[0].frames, 1);
  EXPECT_FLOAT_EQ(texture.bins[0].texels[5], 7.f);
  EXPECT_EQ(texture.bins[1].frames, 0);
  EXPECT_TRUE(texture.bins[1].texels.empty());
  EXPECT_EQ(texture.memoryBytes(), 2u * 2 * 3 * sizeof(float));
}

TEST(SliceTextureBins, TexelsNoFrameSawStayNaNAndOthersIgnoreTheGaps) {
  SliceTextureBins bins({SliceKind::Diagonal, {75, 30}}, 2, 5);
  TextureFrame a = frameAt(90.0, 4.f), b = frameAt(91.0, 6.f);
  for (int c = 0; c < 3; ++c)
    a.texels[3 + c] = b.texels[3 + c] = kNaN;  // texel 1 out of the image in both
  b.texels[0] = kNaN;                          // texel 0 clipped in one
  bins.add(std::move(a));
  bins.add(std::move(b));
  const SliceTexture combined = bins.combine();
  const TextureBin& bin = combined.bins[6];
  EXPECT_FLOAT_EQ(bin.texels[0], 4.f);
  EXPECT_FLOAT_EQ(bin.texels[1], 5.f);
  EXPECT_TRUE(std::isnan(bin.texels[3]));
  EXPECT_THROW(bins.add(frameAt(0.0, 1.f, 3)), btf::BtfError);
  EXPECT_THROW(SliceTextureBins({SliceKind::Axial, {30, 30}}, 2, 0), btf::BtfError);
}

TEST(BtfTexture, StoresTexelTablesInHalfFloatsImageByImage) {
  BtfTexture texture(3);
  EXPECT_EQ(texture.memoryBytes(), 6561u * 9 * 3 * 2);
  const Abrdf table =
      models::tabulate(*models::makeWard({0.2, 0.3, 0.4}, {0.3, 0.3, 0.3}, 0.2, 0.4, 30.0));
  texture.setTexel(4, table);
  const Abrdf back = texture.texel(4);
  for (std::size_t i = 0; i < table.values().size(); ++i)
    EXPECT_NEAR(back.values()[i], table.values()[i], 1e-3 * table.values()[i] + 1e-7);
  EXPECT_EQ(texture.value(10, 20, 4, 1), back.channel(10, 20, 1));
  EXPECT_EQ(texture.value(10, 20, 3, 1), 0.0f);
  // A row written at once is the same as texel by texel.
  BtfTexture byRow(3);
  const std::vector<Abrdf> row{Abrdf(), table, Abrdf()};
  byRow.setRow(1, row);
  for (int light : {0, 33, 80})
    for (int view : {0, 47, 80})
      for (std::size_t i = 0; i < 27; ++i)
        EXPECT_EQ(byRow.image(light, view)[i], texture.image(light, view)[i]);
  EXPECT_THROW(byRow.setRow(0, std::vector<Abrdf>(2)), btf::BtfError);
  // The mean over 9 texels, one of them the table.
  EXPECT_NEAR(averageTable(texture).channel(10, 20, 1), back.channel(10, 20, 1) / 9.0, 1e-6);
}

TEST(BtfFiles, UtiaNamesOfGridDirections) {
  EXPECT_EQ(utiaName({15.0, 60.0}, {30.0, 30.0}), "tl015_pl060_tv030_pv030");
  EXPECT_EQ(imagePath(bonn::indexOf({75.0, 345.0}), 0),
            std::filesystem::path("tv000_pv000/tl075_pl345_tv000_pv000.exr"));
  EXPECT_EQ(imagePath(2, 40).parent_path(), "tv060_pv054");
}

TEST(BtfFiles, DirectoryRoundTripsBitForBitWithAverageManifestAndPreviews) {
  const auto dir = test::freshTempDir() / "btf";
  BtfTexture texture(2);
  for (std::size_t t = 0; t < 4; ++t)
    texture.setTexel(t, models::tabulate(*models::makeWard(Rgb::gray(0.1 * double(t + 1)),
                                                           {0.2, 0.1, 0.3}, 0.2, 0.3, 0.0)));
  const Abrdf average = averageTable(texture);
  writeBtfDirectory(dir, texture, average, {{-20, -20, 20, 20}, "B", "session-1"},
                    {{"method", "B"}}, 2);
  const BtfTexture back = readBtfDirectory(dir);
  ASSERT_EQ(back.resolution(), 2);
  for (int light : {0, 40, 80})
    for (int view : {0, 7, 80})
      for (std::size_t i = 0; i < 12; ++i)
        EXPECT_EQ(back.image(light, view)[i], texture.image(light, view)[i]);
  EXPECT_LT(test::maxAbsDifference(io::readAbrdfExr(dir / "average.exr"), average), 1e-6);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "preview"),
                          std::filesystem::directory_iterator{}),
            8);
  std::ifstream manifest(dir / kBtfManifest);
  const nlohmann::json json = nlohmann::json::parse(manifest);
  EXPECT_EQ(json.at("resolution"), 2);
  EXPECT_EQ(json.at("source"), "session-1");
  EXPECT_DOUBLE_EQ(json.at("texel_mm").get<double>(), 20.0);

  // A missing image is an error naming it.
  std::filesystem::remove(dir / imagePath(5, 6));
  try {
    readBtfDirectory(dir);
    FAIL() << "expected IoError";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(imagePath(5, 6).filename().string()), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(readBtfDirectory(dir / "preview"), io::IoError);
}

// btf.json's resolution was read with nlohmann's get<int>(): undefined behaviour for 1e300, 2 for
// 2.5 (and then an error about an image instead of the field).
TEST(BtfFiles, AResolutionThatIsNoWholeNumberInRangeIsNamed) {
  const auto dir = test::freshTempDir() / "btf";
  std::filesystem::create_directories(dir);
  for (const char* resolution : {"1e300", "2.5", "4294967298", "0", "1025", "\"2\""}) {
    std::ofstream(dir / kBtfManifest)
        << R"({"format": "slicecap-btf", "resolution": )" << resolution << "}";
    try {
      readBtfDirectory(dir);
      ADD_FAILURE() << resolution << " was accepted";
    } catch (const io::IoError& e) {
      EXPECT_NE(std::string(e.what()).find("btf.json: field 'resolution'"), std::string::npos)
          << e.what();
    }
  }
}

// The rest of btf.json a reader relies on: the window (the glTF plane's size; it was read after
// the whole texture fit, unchecked: strings threw an unnamed type error, [0, 0] read past the
// array, a reversed window gave a negative plane) and what the images hold.
TEST(BtfFiles, AManifestWithABadWindowOrAnotherQuantityIsNamed) {
  const auto dir = test::freshTempDir() / "btf";
  std::filesystem::create_directories(dir);
  const std::string good = R"("format": "slicecap-btf", "resolution": 2, "version": 1, )"
                           R"("quantity": "brdf", "unit": "1/sr")";
  for (const auto& [fields, problem] : std::vector<std::pair<std::string, std::string>>{
           {good, "field 'window_mm'"},
           {good + R"(, "window_mm": [0, 0])", "field 'window_mm'"},
           {good + R"(, "window_mm": ["a", "b", "c", "d"])", "field 'window_mm'"},
           {good + R"(, "window_mm": [20, 20, -20, -20])", "field 'window_mm'"},
           {good + R"(, "window_mm": 40)", "field 'window_mm'"},
           {R"("format": "slicecap-btf", "resolution": 2, "window_mm": [-20, -20, 20, 20], )"
            R"("version": 7, "quantity": "brdf", "unit": "1/sr")",
            "field 'version'"},
           {R"("format": "slicecap-btf", "resolution": 2, "window_mm": [-20, -20, 20, 20], )"
            R"("version": 1, "quantity": "radiance", "unit": "1/sr")",
            "field 'quantity'"},
           {R"("format": "slicecap-btf", "resolution": 2, "window_mm": [-20, -20, 20, 20], )"
            R"("version": 1, "quantity": "brdf", "unit": "W")",
            "field 'unit'"}}) {
    std::ofstream(dir / kBtfManifest) << "{" << fields << "}";
    try {
      readBtfManifest(dir);
      ADD_FAILURE() << fields << " was accepted";
    } catch (const io::IoError& e) {
      EXPECT_NE(std::string(e.what()).find("btf.json: " + problem), std::string::npos) << e.what();
    }
  }
  std::ofstream(dir / kBtfManifest) << "{" << good << R"(, "window_mm": [-20, -10, 20, 30]})";
  const BtfManifest manifest = readBtfManifest(dir);
  EXPECT_EQ(manifest.resolution, 2);
  EXPECT_DOUBLE_EQ(manifest.windowMm.yMinMm, -10.0);
  EXPECT_DOUBLE_EQ(manifest.windowMm.heightMm(), 40.0);
}

// A manifest claiming more texels than the images hold was believed until 6561 images of that size
// had been allocated (1024 texels: 41 GB, an allocation failure naming nothing).
TEST(BtfFiles, AResolutionLargerThanTheImagesIsNamedBeforeAllocating) {
  const auto dir = test::freshTempDir() / "btf";
  BtfTexture texture(2);
  for (std::size_t t = 0; t < 4; ++t)
    texture.setTexel(t, models::tabulate(*models::makeLambert(Rgb::gray(0.2))));
  writeBtfDirectory(dir, texture, averageTable(texture), {{-20, -20, 20, 20}, "B", "s"}, {}, 1);
  std::ifstream in(dir / kBtfManifest);
  nlohmann::json manifest = nlohmann::json::parse(in);
  in.close();
  manifest["resolution"] = 1024;
  std::ofstream(dir / kBtfManifest) << manifest.dump();
  try {
    readBtfDirectory(dir);
    ADD_FAILURE() << "a 1024-texel manifest over 2 x 2 images was accepted";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(imagePath(0, 0).filename().string() + ": not 1024 x 1024"),
              std::string::npos)
        << e.what();
  }
}

TEST(BtfFiles, AFailedWriteLeavesEveryImageItWouldReplaceWhole) {
  // The images were written in place: a write cut off (here by a file size limit, as a full disk
  // or a killed run would) left a truncated image where a whole one had been.
  const auto dir = test::freshTempDir() / "btf";
  BtfTexture first(2), second(2);
  for (std::size_t t = 0; t < 4; ++t) {
    first.setTexel(t, models::tabulate(*models::makeLambert(Rgb::gray(0.1 * double(t + 1)))));
    second.setTexel(t, models::tabulate(*models::makeLambert(Rgb::gray(0.05 * double(t + 1)))));
  }
  const BtfDescription description{{-20, -20, 20, 20}, "B", "session-1"};
  writeBtfDirectory(dir, first, averageTable(first), description, {}, 1);
  {
    const test::FileSizeLimit limit(64);  // no image fits
    EXPECT_THROW(writeBtfDirectory(dir, second, averageTable(second), description, {}, 1),
                 io::IoError);
  }
  const BtfTexture back = readBtfDirectory(dir);
  for (int light = 0; light < Abrdf::kDirections; ++light)
    for (int view = 0; view < Abrdf::kDirections; ++view)
      for (std::size_t i = 0; i < 12; ++i)
        ASSERT_EQ(back.image(light, view)[i], first.image(light, view)[i])
            << imagePath(light, view);
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
}

}  // namespace
}  // namespace slicecap::btf
