// Periodic linear interpolation of slices with regular, irregular and duplicate positions.
#include "slicecap/recon/periodic_signal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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
  EXPECT_THROW(PeriodicSignal(std::vector<SignalPoint>{}), std::invalid_argument);
  const std::vector<SignalPoint> nan{{0, Rgb(std::numeric_limits<double>::quiet_NaN(), 0, 0)}};
  EXPECT_THROW((PeriodicSignal(nan)), std::invalid_argument);
}

}  // namespace
}  // namespace slicecap::recon
