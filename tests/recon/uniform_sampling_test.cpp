// The uniform baseline's directions (docs/method.md §6.3) and its point samples.
#include "slicecap/recon/uniform_sampling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

std::set<std::pair<int, int>> anglesOf(const std::vector<int>& directions) {
  std::set<std::pair<int, int>> angles;
  for (int i : directions) {
    const Direction d = bonn::direction(i);
    angles.insert({int(d.thetaDeg), int(std::lround(d.phiDeg))});
  }
  return angles;
}

TEST(UniformSampling, FarthestPointSelectionGivesMethodsThirteenDirections) {
  const std::vector<int> thirteen = farthestPointDirections(13);
  ASSERT_EQ(thirteen.size(), 13u);
  EXPECT_EQ(thirteen.front(), 0) << "starts at the pole";
  const std::set<std::pair<int, int>> expected{
      {0, 0},    {30, 30},  {30, 270}, {45, 140}, {45, 200}, {45, 340}, {60, 54},
      {60, 252}, {60, 288}, {75, 0},   {75, 105}, {75, 165}, {75, 225}};
  EXPECT_EQ(anglesOf(thirteen), expected);
  const std::vector<int> fourteen = farthestPointDirections(14);
  EXPECT_EQ(bonn::direction(fourteen.back()).thetaDeg, 75.0);
  EXPECT_EQ(bonn::direction(fourteen.back()).phiDeg, 315.0);
  EXPECT_EQ(anglesOf(farthestPointDirections(81)).size(), 81u) << "every direction once";
}

TEST(UniformSampling, EveryPickIsAFarthestPointUpToTies) {
  const std::vector<int> order = farthestPointDirections(81);
  auto distance = [](int a, int b) {
    const UnitVector u = toUnitVector(bonn::direction(a)), v = toUnitVector(bonn::direction(b));
    return std::hypot(u.x - v.x, u.y - v.y, u.z - v.z);
  };
  for (std::size_t k = 1; k < order.size(); ++k) {
    auto nearestChosen = [&](int candidate) {
      double d = 10.0;
      for (std::size_t j = 0; j < k; ++j)
        d = std::min(d, distance(candidate, order[j]));
      return d;
    };
    double farthest = 0.0;
    for (std::size_t i = k; i < order.size(); ++i)
      farthest = std::max(farthest, nearestChosen(order[i]));
    EXPECT_NEAR(nearestChosen(order[k]), farthest, 1e-9) << "pick " << k;
  }
}

TEST(UniformSampling, SamplesEveryLightViewPairAtTheTablesValue) {
  const Abrdf table = models::tabulate(*models::findMaterial("satin-blue-45"));
  const SliceSet samples = extractUniformSamples(table, 13);
  EXPECT_EQ(samples.sampleCount(), 169u);
  for (const Slice& slice : samples.slices()) {
    EXPECT_EQ(slice.id.kind, SliceKind::Point);
    for (const SliceSample& s : slice.samples) {
      EXPECT_EQ(s.value, table.at(bonn::indexOf(s.light), bonn::indexOf(s.view)));
      EXPECT_EQ(slice.id.elevations.thetaIDeg, int(s.light.thetaDeg));
    }
  }
}

TEST(UniformSampling, RejectsCountsOutsideTheGrid) {
  EXPECT_THROW(farthestPointDirections(0), recon::ReconArgumentError);
  EXPECT_THROW(farthestPointDirections(82), recon::ReconArgumentError);
  EXPECT_THROW(extractUniformSamples(Abrdf(), -1), recon::ReconArgumentError);
}

}  // namespace
}  // namespace slicecap::recon
