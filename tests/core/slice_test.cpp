// Slice kinds, the slice line's parametrisation and the SliceSet container.
#include "slicecap/core/slice.hpp"

#include <gtest/gtest.h>

#include "slicecap/core/abrdf.hpp"

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
