// Periodic linear interpolation of slices with regular, irregular and duplicate positions.
#include "slicecap/recon/periodic_signal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

TEST(PeriodicSignal, InterpolatesLinearlyAndWraps) {
  const std::vector<SignalPoint> points{
      {0, Rgb::gray(0)}, {90, Rgb::gray(1)}, {180, Rgb::gray(2)}, {270, Rgb::gray(3)}};
  const PeriodicSignal s(points);
  EXPECT_DOUBLE_EQ(s.at(45).r(), 0.5);
  EXPECT_DOUBLE_EQ(s.at(270).r(), 3.0);
  EXPECT_DOUBLE_EQ(s.at(315).r(), 1.5) << "between the last sample and the first, across 360";
  EXPECT_DOUBLE_EQ(s.at(-45).r(), 1.5);
  EXPECT_DOUBLE_EQ(s.at(405).r(), 0.5);
  EXPECT_DOUBLE_EQ(s.minimum().r(), 0.0);
  EXPECT_DOUBLE_EQ(s.maximum().r(), 3.0);
}

// The slice sums read a signal along a ring with a cursor; whatever the cursor holds, the value
// must be the binary search's, at sample positions, between them, across 360 and on a gap.
TEST(PeriodicSignal, CursorReadsTheSameValuesAsTheSearch) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> position(0.0, 360.0), value(0.0, 5.0);
  for (std::size_t count : {1u, 2u, 7u, 24u}) {
    std::vector<SignalPoint> points;
    for (std::size_t i = 0; i < count; ++i)
      points.push_back({position(rng), {value(rng), value(rng), value(rng)}});
    points.push_back(points.front());  // a duplicate position, averaged
    const PeriodicSignal s(points);
    std::vector<double> queries{-400.0, -0.5, 0.0, 359.999, 360.0, 725.0};
    for (const SignalPoint& p : s.points())
      queries.push_back(p.positionDeg);
    for (int i = 0; i < 200; ++i)
      queries.push_back(position(rng) * 2.0 - 180.0);
    std::size_t cursor = 0;
    for (std::size_t start : {std::size_t{0}, count / 2, count + 5}) {
      cursor = start;
      for (double x : queries)
        ASSERT_EQ(s.at(x, cursor), s.at(x)) << count << " points, at " << x;
    }
    for (std::size_t i = 0; i < 360; ++i)  // in order, as along a ring
      ASSERT_EQ(s.at(double(i), cursor), s.at(double(i))) << count << " points, at " << i;
  }
}

TEST(PeriodicSignal, HandlesIrregularAndMissingSamples) {
  // A capture with jitter and a gap from 100 to 350 deg.
  const std::vector<SignalPoint> points{
      {352, Rgb::gray(4)}, {10, Rgb::gray(1)}, {100, Rgb::gray(2)}};
  const PeriodicSignal s(points);
  EXPECT_NEAR(s.at(1).r(), 4.0 + (1.0 - 4.0) * (9.0 / 18.0), 1e-12);
  EXPECT_NEAR(s.at(226).r(), 2.0 + (4.0 - 2.0) * (126.0 / 252.0), 1e-12);
}

TEST(PeriodicSignal, AveragesSamplesAtOnePositionAndKeepsChannelsApart) {
  const std::vector<SignalPoint> points{
      {30, {1, 10, 100}}, {30, {3, 30, 300}}, {390 - 180, {0, 0, 0}}};
  const PeriodicSignal s(points);
  ASSERT_EQ(s.points().size(), 2u);
  EXPECT_EQ(s.at(30), Rgb(2, 20, 200));
}

TEST(PeriodicSignal, SingleSampleIsConstant) {
  const std::vector<SignalPoint> points{{123, Rgb(1, 2, 3)}};
  EXPECT_EQ(PeriodicSignal(points).at(7), Rgb(1, 2, 3));
}

TEST(PeriodicSignal, RejectsEmptyAndNonFiniteInput) {
  EXPECT_THROW(PeriodicSignal(std::vector<SignalPoint>{}), recon::ReconArgumentError);
  const std::vector<SignalPoint> nan{{0, Rgb(std::numeric_limits<double>::quiet_NaN(), 0, 0)}};
  EXPECT_THROW((PeriodicSignal(nan)), recon::ReconArgumentError);
}

}  // namespace
}  // namespace slicecap::recon
