// Slice kinds, the slice line's parametrisation and the SliceSet container.
#include "slicecap/core/slice.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/core_error.hpp"

namespace slicecap {
namespace {

TEST(Slice, KindsParseAndPrint) {
  EXPECT_EQ(parseSliceKind("axial"), SliceKind::Axial);
  EXPECT_EQ(parseSliceKind("diagonal"), SliceKind::Diagonal);
  EXPECT_FALSE(parseSliceKind("Axial").has_value());
  EXPECT_FALSE(parseSliceKind("diag").has_value());
  EXPECT_EQ(toString(SliceId{SliceKind::Axial, {30, 75}}), "axial 30/75");
}

TEST(Slice, PointsAndParametersAreInverse) {
  for (double x = 0.0; x < 360.0; x += 7.5) {
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      const AzimuthPair p = slicePoint(kind, x);
      const SliceSample s{{30, p.phiIDeg}, {75, p.phiVDeg}, {}};
      EXPECT_NEAR(sliceParameterDeg(kind, s), x, 1e-12);
    }
  }
  // Axial keeps a 15 deg offset; diagonal mirrors the light.
  EXPECT_DOUBLE_EQ(slicePoint(SliceKind::Axial, 350.0).phiVDeg, 5.0);
  EXPECT_DOUBLE_EQ(slicePoint(SliceKind::Diagonal, 30.0).phiIDeg, 330.0);
  EXPECT_DOUBLE_EQ(slicePoint(SliceKind::Diagonal, 0.0).phiIDeg, 0.0);
}

TEST(SliceSet, GroupsSamplesBySliceInIdOrder) {
  SliceSet set;
  set.add({SliceKind::Diagonal, {75, 75}}, {{75, 0}, {75, 0}, Rgb::gray(1)});
  set.add({SliceKind::Axial, {30, 30}}, {{30, 0}, {30, 15}, Rgb::gray(2)});
  set.add({SliceKind::Diagonal, {75, 75}}, {{75, 345}, {75, 15}, Rgb::gray(3)});
  ASSERT_EQ(set.slices().size(), 2u);
  EXPECT_EQ(set.slices()[0].id.kind, SliceKind::Axial);
  EXPECT_EQ(set.sampleCount(), 3u);
  const Slice* d = set.find({SliceKind::Diagonal, {75, 75}});
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->samples.size(), 2u);
  EXPECT_EQ(d->samples[1].value, Rgb::gray(3)) << "capture order is kept";
  EXPECT_EQ(set.find({SliceKind::Axial, {75, 75}}), nullptr);
}

// A capture's second reading of a slice (its window cells'): kept apart from the samples, read
// instead of them by cellReading, and only for a slice that has samples.
TEST(SliceSet, CellSamplesAreASecondReadingOfASliceWithSamples) {
  SliceSet set;
  const SliceId axial{SliceKind::Axial, {30, 30}}, diagonal{SliceKind::Diagonal, {75, 75}};
  set.add(axial, {{30, 0}, {30, 15}, Rgb::gray(2)});
  set.add(diagonal, {{75, 0}, {75, 0}, Rgb::gray(1)});
  EXPECT_THROW(set.addCellSample({SliceKind::Axial, {75, 75}}, {{75, 0}, {75, 15}, Rgb::gray(4)}),
               slicecap::CoreError);
  EXPECT_FALSE(set.hasCellSamples());
  set.addCellSample(axial, {{30, 1}, {30, 16}, Rgb::gray(5)});
  set.addCellSample(axial, {{30, 14}, {30, 29}, Rgb::gray(6)});
  EXPECT_TRUE(set.hasCellSamples());
  EXPECT_EQ(set.sampleCount(), 2u) << "cell samples are not the slices' samples";
  const SliceSet reading = set.cellReading();
  EXPECT_EQ(reading.find(axial)->samples.size(), 2u);
  EXPECT_EQ(reading.find(axial)->samples[1].value, Rgb::gray(6));
  EXPECT_EQ(reading.find(diagonal)->samples[0].value, Rgb::gray(1)) << "no cells: the samples";
  EXPECT_FALSE(reading.hasCellSamples());
}

TEST(Abrdf, StoresLightMajorRgb) {
  Abrdf table;
  table.set(2, 8, {1, 2, 3});
  EXPECT_EQ(table.at(2, 8), Rgb(1, 2, 3));
  EXPECT_EQ(table.values()[(2 * 81 + 8) * 3 + 2], 3.0f);
  EXPECT_EQ(table.channel(2, 8, 1), 2.0f);
  EXPECT_EQ(table.at(8, 2), Rgb());
}

}  // namespace
}  // namespace slicecap
