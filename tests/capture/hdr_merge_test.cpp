// The per-bin HDR merge: clipped and dark cells out, inverse-variance weights, irradiance by the
// references' SNR; the window centre from curving cells; frames that see different values;
// bins without HDR readings keep the median.
#include "slicecap/capture/hdr_merge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slicecap/capture/azimuth_bins.hpp"

namespace slicecap::capture {
namespace {

constexpr double kIrradiance = 10.0;
constexpr std::size_t kCells = kHdrCellsPerSide * kHdrCellsPerSide;

// A frame of exposure x gain `scale` (units per unit radiance) reading a window whose cells all
// have `radiance` per unit exposure, on an 8-bit-like sensor: full scale 1, clipped at 0.98,
// variance (read 0.002 + shot) / scale^2.
FrameSample frameAt(double scale, double radiance, double parameterDeg = 90.0) {
  FrameSample s;
  s.light = {30.0, 360.0 - parameterDeg};
  s.view = {30.0, parameterDeg};
  HdrReading hdr;
  for (std::size_t k = 0; k < kCells; ++k) {
    HdrCell cell;
    const double level = radiance * scale;
    cell.level = std::min(level, 1.0);
    cell.clipped = level >= 0.98;
    // What a clipped cell reads: full scale, far below the truth.
    const double read = std::min(level, 1.0) / scale;
    cell.radiance = {read, read, read};
    const double variance = (0.002 * 0.002 + level / 8000.0) / (scale * scale);
    cell.variance = {variance, variance, variance};
    hdr.cells.push_back(cell);
  }
  hdr.irradiance = {kIrradiance, kIrradiance, kIrradiance};
  hdr.irradianceWeight = scale;  // brighter references: a surer irradiance
  s.value = hdr.cells.front().radiance * (1.0 / kIrradiance);
  s.hdr = std::move(hdr);
  return s;
}

TEST(HdrMerge, RecoversAValueThatClipsInTheLongExposure) {
  const double radiance = 2.0;  // x 16 = 32 x full scale in the long frame
  const FrameSample longFrame = frameAt(16.0, radiance);
  const FrameSample shortFrame = frameAt(0.25, radiance);  // at 0.5 of full scale
  ASSERT_TRUE(longFrame.hdr->cells.front().clipped);
  ASSERT_NEAR(longFrame.value[0], 1.0 / 16.0 / kIrradiance, 1e-12);  // what one frame says
  const auto merged = mergeHdrBin({longFrame, shortFrame});
  ASSERT_TRUE(merged);
  EXPECT_NEAR(merged->value[0], radiance / kIrradiance, 1e-9);
  EXPECT_EQ(merged->clippedCells, 0);
}

TEST(HdrMerge, WeighsTheLongExposureMoreWhereNeitherClips) {
  FrameSample longFrame = frameAt(16.0, 0.01);
  FrameSample shortFrame = frameAt(1.0, 0.01);
  // Noise in each: the long frame's reading is off by 1 %, the short one's by 20 %.
  for (HdrCell& c : longFrame.hdr->cells) c.radiance = {0.0101, 0.0101, 0.0101};
  for (HdrCell& c : shortFrame.hdr->cells) c.radiance = {0.012, 0.012, 0.012};
  const auto merged = mergeHdrBin({shortFrame, longFrame});
  ASSERT_TRUE(merged);
  // The long frame's variance is ~100 x smaller: the merge stays within 1.5 % of the truth.
  EXPECT_NEAR(merged->value[1] * kIrradiance, 0.01, 0.00015);
  EXPECT_GT(merged->value[1] * kIrradiance, 0.0101 - 1e-9);
}

TEST(HdrMerge, LeavesOutATooDarkReadingWhenAnotherFrameReadsTheCellBrighter) {
  FrameSample longFrame = frameAt(16.0, 0.01);  // level 0.16
  FrameSample shortFrame = frameAt(0.1, 0.01);  // level 0.001: a code or two of 8 bits
  // A dark reading's bias (quantisation, room light) is not in its variance: give it none.
  for (HdrCell& c : shortFrame.hdr->cells) {
    c.radiance = {0.05, 0.05, 0.05};
    c.variance = {1e-12, 1e-12, 1e-12};
  }
  const auto merged = mergeHdrBin({longFrame, shortFrame});
  ASSERT_TRUE(merged);
  EXPECT_NEAR(merged->value[0] * kIrradiance, 0.01, 1e-9);
}

TEST(HdrMerge, ACellClippedInEveryFrameGivesItsLargestReadingAndIsCounted) {
  const auto merged = mergeHdrBin({frameAt(16.0, 100.0), frameAt(4.0, 100.0)});
  ASSERT_TRUE(merged);
  EXPECT_EQ(merged->clippedCells, static_cast<int>(kCells));
  EXPECT_NEAR(merged->value[0] * kIrradiance, 1.0 / 4.0, 1e-9);
}

TEST(HdrMerge, IrradianceWeighsTheSurerReferences) {
  FrameSample longFrame = frameAt(16.0, 0.01);
  FrameSample shortFrame = frameAt(1.0, 0.01);
  shortFrame.hdr->irradiance = {5.0, 5.0, 5.0};  // a noisy fit
  shortFrame.hdr->irradianceWeight = 0.0;
  const auto merged = mergeHdrBin({longFrame, shortFrame});
  ASSERT_TRUE(merged);
  EXPECT_NEAR(merged->value[2] * kIrradiance, 0.01, 2e-4);
}

// A sharp lobe across the sample square: a cell's radiance is the mean over the cell of
// peak * exp(-(x / width)^2), x in [-1, 1] across the square (a Ward lobe of ax 0.04 at 75/75
// elevations and 300 mm: the half vector tilts by 1.27 ax over the square's half-width).
FrameSample lobeFrame(double scale, double peak, double width) {
  FrameSample s = frameAt(scale, peak);
  for (int j = 0; j < kHdrCellsPerSide; ++j)
    for (int i = 0; i < kHdrCellsPerSide; ++i) {
      double sum = 0.0;
      constexpr int kSteps = 100;
      for (int k = 0; k < kSteps; ++k) {
        const double x = -1.0 + (i + (k + 0.5) / kSteps) * 2.0 / kHdrCellsPerSide;
        sum += peak * std::exp(-(x / width) * (x / width)) / kSteps;
      }
      HdrCell& cell = s.hdr->cells[j * kHdrCellsPerSide + i];
      cell.radiance = {sum, sum, sum};
      cell.level = sum * scale;
      const double variance = (0.002 * 0.002 + sum * scale / 8000.0) / (scale * scale);
      cell.variance = {variance, variance, variance};
    }
  return s;
}

TEST(HdrMerge, ALobeCurvingAcrossTheSquareGivesTheCentresValueNotTheSquaresMean) {
  const double peak = 2.0, width = 1.0 / 1.27;
  const auto merged = mergeHdrBin({lobeFrame(0.35, peak, width)});  // the centre at 70 %
  ASSERT_TRUE(merged);
  EXPECT_TRUE(merged->centreFromCurve);
  // The square's mean is ~0.65 of the peak; the quadratic surface's centre ~0.94.
  EXPECT_NEAR(merged->value[1] * kIrradiance / peak, 0.94, 0.03);
}

TEST(HdrMerge, FlatCellsWithNoiseKeepTheirMean) {
  std::mt19937 rng(7);
  int curved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    FrameSample s = frameAt(16.0, 0.01);
    double sum = 0.0;
    for (HdrCell& c : s.hdr->cells) {
      std::normal_distribution<double> noise(0.0, std::sqrt(c.variance[0]));
      const double v = 0.01 + noise(rng);
      c.radiance = {v, v, v};
      sum += v;
    }
    const auto merged = mergeHdrBin({s});
    ASSERT_TRUE(merged);
    curved += merged->centreFromCurve ? 1 : 0;
    if (!merged->centreFromCurve) {
      EXPECT_NEAR(merged->value[0] * kIrradiance, sum / double(kCells), 1e-12);
    }
  }
  // A 3-sigma test on the channels' mean (variance / 3): a false alarm a few times in 1000.
  EXPECT_LE(curved, 3);
}

TEST(HdrMerge, FramesThatSeeDifferentValuesGiveTheOneNearestTheBinCentre) {
  // The long frame 2.5 deg off the centre, off a narrow lobe (0.0074 1/sr x irradiance); the
  // short one 0.05 deg off, on it. Inverse-variance weights would keep the long frame's value.
  const FrameSample offLobe = frameAt(4.0, 0.074);
  const FrameSample onLobe = frameAt(0.04, 20.0);
  const auto merged = mergeHdrBin({offLobe, onLobe}, {-2.5, -0.05});
  ASSERT_TRUE(merged);
  EXPECT_NEAR(merged->value[0] * kIrradiance, 20.0, 1e-9);
  // Frames that agree within noise are still averaged by their variances.
  const auto agreeing = mergeHdrBin({frameAt(16.0, 0.01), frameAt(1.0, 0.0102)}, {-2.5, 0.0});
  ASSERT_TRUE(agreeing);
  EXPECT_NEAR(agreeing->value[0] * kIrradiance, 0.01, 1e-4);
}

TEST(HdrMerge, AFrameClippedBrighterThanTheOthersReadIsNotOverruled) {
  // The frame nearest the centre clips (the lobe brighter than its full scale, 1 / 16); the other,
  // off the lobe, reads 0.01: the bin is the clipped frame's lower bound, counted as clipped.
  const auto merged = mergeHdrBin({frameAt(16.0, 2.0), frameAt(1.0, 0.01)}, {0.2, 3.0});
  ASSERT_TRUE(merged);
  EXPECT_NEAR(merged->value[0] * kIrradiance, 1.0 / 16.0, 1e-9);
  EXPECT_EQ(merged->clippedCells, static_cast<int>(kCells));
}

TEST(HdrMerge, SamplesWithoutReadingsAreNoHdrBin) {
  FrameSample plain = frameAt(1.0, 0.01);
  plain.hdr.reset();
  EXPECT_FALSE(mergeHdrBin({plain, frameAt(1.0, 0.01)}));
  EXPECT_FALSE(mergeHdrBin({}));
}

TEST(HdrMerge, AzimuthBinsMergeHdrSamplesAndKeepTheMedianOtherwise) {
  AzimuthBins hdrBins(SliceKind::Diagonal);
  hdrBins.add(frameAt(16.0, 2.0));
  hdrBins.add(frameAt(0.25, 2.0));
  const auto merged = hdrBins.combine();
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_NEAR(merged[0].value[0], 2.0 / kIrradiance, 1e-9);

  AzimuthBins plainBins(SliceKind::Diagonal);
  for (double scale : {16.0, 0.25, 0.5}) {
    FrameSample s = frameAt(scale, 2.0);
    s.hdr.reset();
    plainBins.add(s);
  }
  const auto median = plainBins.combine();
  ASSERT_EQ(median.size(), 1u);
  EXPECT_NEAR(median[0].value[0], 2.0 / kIrradiance, 1e-9);  // the median of 1/16, 2, 2
}

TEST(HdrMerge, AzimuthBinsNameTheBinsClippedAtEveryExposure) {
  AzimuthBins bins(SliceKind::Diagonal);
  // Bin 6 (90 deg): clipped in its long frame only, the short one holds it.
  bins.add(frameAt(16.0, 2.0, 90.0));
  bins.add(frameAt(0.25, 2.0, 90.0));
  // Bin 18 (270 deg): only a long frame, clipped; bin 12 (180 deg): clipped at both exposures.
  bins.add(frameAt(16.0, 2.0, 270.0));
  bins.add(frameAt(16.0, 100.0, 180.0));
  bins.add(frameAt(4.0, 100.0, 180.0));
  // Bin 3 (45 deg): dim, nothing clipped.
  bins.add(frameAt(16.0, 0.01, 45.0));
  EXPECT_EQ(bins.clippedBins(), (std::vector<int>{12, 18}));

  // Frames that disagree (a clipped reading brighter than an unclipped one: the lobe moved
  // between them): the one nearest the bin centre gives the value, so it says whether the bin
  // rests on a clipped cell, whichever frame came first.
  const FrameSample clippedNear = frameAt(0.5, 3.0, 90.5), clearFar = frameAt(0.25, 1.0, 95.0);
  const FrameSample clippedFar = frameAt(0.5, 3.0, 95.0), clearNear = frameAt(0.25, 1.0, 90.5);
  ASSERT_TRUE(clippedNear.hdr->cells.front().clipped);
  ASSERT_FALSE(clearFar.hdr->cells.front().clipped);
  for (const bool clippedFirst : {true, false}) {
    AzimuthBins near(SliceKind::Diagonal), far(SliceKind::Diagonal);
    near.add(clippedFirst ? clippedNear : clearFar);
    near.add(clippedFirst ? clearFar : clippedNear);
    far.add(clippedFirst ? clippedFar : clearNear);
    far.add(clippedFirst ? clearNear : clippedFar);
    EXPECT_EQ(near.clippedBins(), std::vector<int>{6}) << "clipped frame first: " << clippedFirst;
    EXPECT_TRUE(far.clippedBins().empty()) << "clipped frame first: " << clippedFirst;
    EXPECT_NEAR(far.combine().at(0).value[0] * kIrradiance, 1.0, 1e-9);
  }
  // A sample added after an answer changes it (the answer is kept only until the bins change).
  AzimuthBins growing(SliceKind::Diagonal);
  growing.add(frameAt(16.0, 0.01, 48.0));
  EXPECT_TRUE(growing.clippedBins().empty());
  growing.add(frameAt(4.0, 100.0, 45.0));  // nearer the centre, clipped, brighter: it decides
  EXPECT_EQ(growing.clippedBins(), std::vector<int>{3});

  AzimuthBins plainBins(SliceKind::Diagonal);
  FrameSample clipped = frameAt(16.0, 100.0, 180.0);
  clipped.hdr.reset();  // one exposure: no cells, so nothing to say (its gate rejects clipping)
  plainBins.add(clipped);
  EXPECT_TRUE(plainBins.clippedBins().empty());
}

}  // namespace
}  // namespace slicecap::capture
