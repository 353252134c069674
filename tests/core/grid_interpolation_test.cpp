// Interpolation of a table at arbitrary directions: exact on the grid, linear between, clamped
// above 75.
#include "slicecap/core/grid_interpolation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>

#include "slicecap/core/core_error.hpp"

namespace slicecap {
namespace {

Abrdf indexTable() {
  Abrdf t;
  for (int l = 0; l < 81; ++l) {
    for (int v = 0; v < 81; ++v)
      t.set(l, v, {double(l), double(v), double(l * 81 + v)});
  }
  return t;
}

double weightSum(const std::vector<DirectionTap>& taps) {
  return std::accumulate(taps.begin(), taps.end(), 0.0,
                         [](double s, const DirectionTap& t) { return s + t.weight; });
}

TEST(GridInterpolation, IsExactOnTheGrid) {
  const Abrdf table = indexTable();
  for (int l = 0; l < 81; l += 7) {
    for (int v = 0; v < 81; v += 5) {
      EXPECT_EQ(evaluate(table, bonn::direction(l), bonn::direction(v)), table.at(l, v));
      EXPECT_EQ(tableTaps(bonn::direction(l), bonn::direction(v)).size(), 1u);
    }
  }
}

TEST(GridInterpolation, IsLinearInAzimuthAndElevation) {
  const Abrdf table = indexTable();
  // Azimuth 15 on the 30 ring: halfway between indices 7 and 8.
  EXPECT_DOUBLE_EQ(evaluate(table, {30, 15}, {0, 0}).r(), 7.5);
  // Across 360 on the 75 ring: between 80 (345) and 57 (0).
  EXPECT_DOUBLE_EQ(evaluate(table, {75, 352.5}, {0, 0}).r(), 0.5 * 80 + 0.5 * 57);
  // Elevation 37.5 at azimuth 0: halfway between (30, 0) = 7 and (45, 0) = 19.
  EXPECT_DOUBLE_EQ(evaluate(table, {0, 0}, {37.5, 0}).g(), 13.0);
  // Near the pole every azimuth blends with the single pole direction.
  const auto taps = directionTaps({5, 100});
  EXPECT_NEAR(weightSum(taps), 1.0, 1e-12);
  EXPECT_EQ(taps.size(), 3u);
}

TEST(GridInterpolation, ClampsAboveTheLastRingAndRejectsBadDirections) {
  const Abrdf table = indexTable();
  EXPECT_EQ(evaluate(table, {85, 30}, {0, 0}), evaluate(table, {75, 30}, {0, 0}));
  EXPECT_THROW(directionTaps({-1, 0}), slicecap::CoreError);
  EXPECT_THROW(directionTaps({std::numeric_limits<double>::quiet_NaN(), 0}), slicecap::CoreError);
}

TEST(GridInterpolation, WeightsAlwaysSumToOne) {
  for (double theta = 0; theta < 90; theta += 3.7) {
    for (double phi = -30; phi < 400; phi += 11.3)
      EXPECT_NEAR(weightSum(directionTaps({theta, phi})), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace slicecap
