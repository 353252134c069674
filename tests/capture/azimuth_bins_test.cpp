// Azimuth bins: boundaries, robust medians, circular means of angles across 0/360.
#include "slicecap/capture/azimuth_bins.hpp"

#include <gtest/gtest.h>

#include "slicecap/capture/capture_error.hpp"

namespace slicecap::capture {
namespace {

FrameSample diagonalAt(double phiVDeg, double value, double thetaVDeg = 75.0) {
  return {0, 0, {30.0, 360.0 - phiVDeg}, {thetaVDeg, phiVDeg}, Rgb::gray(value)};
}

TEST(AzimuthBins, CentresBinsOnTheIdealSamplePositions) {
  const AzimuthBins bins(SliceKind::Diagonal);
  EXPECT_EQ(bins.binCount(), 24);
  EXPECT_EQ(bins.binOf(0.0), 0);
  EXPECT_EQ(bins.binOf(7.49), 0);
  EXPECT_EQ(bins.binOf(7.5), 1);
  EXPECT_EQ(bins.binOf(352.6), 0) << "wraps: the last half bin belongs to bin 0";
  EXPECT_EQ(bins.binOf(352.4), 23);
  EXPECT_EQ(bins.binOf(-15.0), 23);
  EXPECT_THROW(AzimuthBins(SliceKind::Axial, 7.0), capture::CaptureError);
}

TEST(AzimuthBins, AxialSlicesBinByTheLightAzimuth) {
  AzimuthBins bins(SliceKind::Axial);
  bins.add({0, 0, {75, 44.0}, {75, 59.0}, Rgb::gray(1)});
  EXPECT_EQ(bins.filled()[3], true) << "light azimuth 44 is bin 3 (45 deg), not the view's 59";
  EXPECT_EQ(bins.filledCount(), 1);
}

TEST(AzimuthBins, MedianIgnoresAnOutlierAndAnglesAreTheFramesMean) {
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(diagonalAt(358.0, 1.0, 74.0));
  bins.add(diagonalAt(2.0, 1.2, 76.0));
  bins.add(diagonalAt(1.0, 50.0, 75.0));  // an occluded frame that passed the gate
  bins.add(diagonalAt(90.0, 3.0));
  const std::vector<SliceSample> samples = bins.combine();
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[0].value.r(), 1.2);
  EXPECT_NEAR(samples[0].view.phiDeg, 0.333333, 1e-3) << "circular mean across 360";
  EXPECT_NEAR(samples[0].view.thetaDeg, 75.0, 1e-12);
  EXPECT_NEAR(samples[0].light.phiDeg, 359.666667, 1e-3);
  EXPECT_DOUBLE_EQ(samples[1].value.g(), 3.0);
}

TEST(AzimuthBins, EvenCountsTakeTheMiddleMean) {
  AzimuthBins bins(SliceKind::Diagonal);
  for (double v : {4.0, 1.0, 3.0, 2.0})
    bins.add(diagonalAt(30.0, v));
  EXPECT_DOUBLE_EQ(bins.combine()[0].value.b(), 2.5);
  bins.clear();
  EXPECT_EQ(bins.filledCount(), 0);
}

TEST(AzimuthBins, AVersionChangesWithTheBinsAndIsNoOtherBinsOwn) {
  AzimuthBins bins(SliceKind::Axial), other(SliceKind::Axial);
  const std::uint64_t fresh = bins.version();
  EXPECT_NE(other.version(), fresh);
  bins.add(FrameSample{0, 0, {30, 0}, {30, 15}, Rgb::gray(0.5)});
  const std::uint64_t added = bins.version();
  EXPECT_NE(added, fresh);
  bins.clear();
  EXPECT_NE(bins.version(), added);
  EXPECT_NE(bins.version(), fresh) << "emptied again, but not the same bins as at first";
}

}  // namespace
}  // namespace slicecap::capture
