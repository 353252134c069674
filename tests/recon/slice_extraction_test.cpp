// Simulated acquisition: sample counts, grid coincidences and lookup weights of docs/method.md §2.2-2.3.
#include "slicecap/recon/slice_extraction.hpp"

#include <gtest/gtest.h>

#include <set>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

Abrdf indexTable() {
  Abrdf t;
  for (int l = 0; l < 81; ++l) {
    for (int v = 0; v < 81; ++v)
      t.set(l, v, {double(l), double(v), double(l * 81 + v)});
  }
  return t;
}

std::set<std::pair<int, int>> touchedImages(AzimuthLookup lookup) {
  std::set<std::pair<int, int>> images;
  for (ElevationPair pair : kMeasuredPairs) {
    const int count = samplesPerSlice(pair, {});
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      for (int k = 0; k < count; ++k) {
        for (const GridWeight& w :
             lookupWeights(pair, slicePoint(kind, k * 360.0 / count), lookup)) {
          images.insert({w.light, w.view});
        }
      }
    }
  }
  return images;
}

TEST(SliceExtraction, TakesThePapersSampleCounts) {
  const Abrdf table = indexTable();
  EXPECT_EQ(extractSlices(table).sampleCount(), 168u);
  ExtractionParams diagonal;
  diagonal.diagonalOnly = true;
  EXPECT_EQ(extractSlices(table, diagonal).sampleCount(), 84u);
  ExtractionParams every15;
  every15.stepDeg = 15.0;
  EXPECT_EQ(extractSlices(table, every15).sampleCount(), 192u);
  const SliceSet slices = extractSlices(table);
  EXPECT_EQ(slices.find({SliceKind::Axial, {30, 30}})->samples.size(), 12u);
  EXPECT_EQ(slices.find({SliceKind::Diagonal, {75, 30}})->samples.size(), 24u);
}

TEST(SliceExtraction, TouchesTheDocumentedNumberOfImages) {
  EXPECT_EQ(touchedImages(AzimuthLookup::Linear).size(), 218u);
  EXPECT_EQ(touchedImages(AzimuthLookup::Nearest).size(), 162u);
}

TEST(SliceExtraction, OnGridSamplesAreExactTableValues) {
  const Abrdf table = indexTable();
  int onGrid = 0;
  const SliceSet slices = extractSlices(table);
  for (const Slice& slice : slices.slices()) {
    for (const SliceSample& s : slice.samples) {
      const auto weights = lookupWeights(slice.id.elevations, {s.light.phiDeg, s.view.phiDeg});
      if (weights.size() != 1) continue;
      ++onGrid;
      EXPECT_EQ(s.value, table.at(bonn::indexOf(s.light), bonn::indexOf(s.view)));
    }
  }
  EXPECT_EQ(onGrid, 108) << "docs/method.md §2.2: 108 of the 168 samples fall on the grid";
}

TEST(SliceExtraction, InterpolatesAlongTheCoarserRing) {
  const Abrdf table = indexTable();
  // Axial 30/30 at x = 0: light (30, 0) = index 7, view (30, 15) halfway between 7 and 8.
  const Rgb value = sampleTable(table, {30, 30}, {0.0, 15.0});
  EXPECT_DOUBLE_EQ(value.g(), 7.5);
  EXPECT_DOUBLE_EQ(value.r(), 7.0);
  // Nearest breaks the exact half-step tie toward the lower index.
  EXPECT_DOUBLE_EQ(sampleTable(table, {30, 30}, {0.0, 15.0}, AzimuthLookup::Nearest).g(), 7.0);
  EXPECT_DOUBLE_EQ(sampleTable(table, {30, 30}, {0.0, 16.0}, AzimuthLookup::Nearest).g(), 8.0);
  // Across 360: view (30, 345) lies between indices 18 and 7.
  EXPECT_DOUBLE_EQ(sampleTable(table, {30, 30}, {0.0, 345.0}).g(), 12.5);
}

TEST(SliceExtraction, SamplesCarryTheirDirections) {
  const SliceSet slices = extractSlices(indexTable());
  const Slice* axial = slices.find({SliceKind::Axial, {75, 30}});
  ASSERT_NE(axial, nullptr);
  const SliceSample& s = axial->samples[3];
  EXPECT_DOUBLE_EQ(s.light.thetaDeg, 75.0);
  EXPECT_DOUBLE_EQ(s.view.thetaDeg, 30.0);
  EXPECT_DOUBLE_EQ(s.light.phiDeg, 45.0);
  EXPECT_DOUBLE_EQ(s.view.phiDeg, 60.0);
}

TEST(SliceExtraction, RejectsAStepThatDoesNotDivide360) {
  ExtractionParams params;
  params.stepDeg = 7.0;
  std::string why;
  EXPECT_FALSE(params.isValid(&why));
  EXPECT_FALSE(why.empty());
  EXPECT_THROW(extractSlices(indexTable(), params), recon::ReconArgumentError);
  params.stepDeg = 0.0;
  EXPECT_FALSE(params.isValid(nullptr));
}

}  // namespace
}  // namespace slicecap::recon
