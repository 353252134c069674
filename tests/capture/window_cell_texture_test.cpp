// Texture in a sweep's window cells: a fixed per-cell albedo pattern is found and divided out; a
// sharp lobe on a plain material is left as read; texture whose spots differ in their lobes, not
// by a factor, gives the window centres' reading.
#include "slicecap/capture/window_cell_texture.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "slicecap/capture/window_cells.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::capture {
namespace {

using ::testing::HasSubstr;

constexpr int kSide = 8;
const SliceId kDiagonal7575{SliceKind::Diagonal, {75, 75}};
const SliceId kAxial7575{SliceKind::Axial, {75, 75}};
const SliceId kAxial3030{SliceKind::Axial, {30, 30}};

// What a cell at position `k` (row by row) reads at its own directions.
using CellValue = std::function<Rgb(int k, const UnitVector& toLight, const UnitVector& toView)>;

std::array<double, 3> at(const Direction& d, double distanceMm) {
  const UnitVector u = toUnitVector(d);
  return {distanceMm * u.x, distanceMm * u.y, distanceMm * u.z};
}

Rgb times(const Rgb& a, const Rgb& b) { return {a[0] * b[0], a[1] * b[1], a[2] * b[2]}; }

// A 75/75 sweep of `kind` as the rig sees it: a frame every 3 deg of the slice parameter, the
// LED and the camera 300 mm from the window centre, 8 x 8 cells over the 40 mm window placed by
// the same geometry as the pipeline's (placeCellDirections). On an axial sweep (the light and
// the view turning together) cells of neighbouring frames meet at the same directions in every
// bin; on a diagonal one (turning apart) in a quarter of them.
AzimuthBins sweep(const CellValue& valueAt, SliceKind kind = SliceKind::Diagonal,
                  double elevationDeg = 75.0, double noiseSigma = 0.0) {
  AzimuthBins bins(kind);
  for (int f = 0; f < 120; ++f) {
    const AzimuthPair azimuths = slicePoint(kind, 3.0 * f + 1.0);
    const Direction light{elevationDeg, azimuths.phiIDeg}, view{elevationDeg, azimuths.phiVDeg};
    WindowCells cells;
    cells.cellsPerSide = kSide;
    cells.gridMm = {-20, -20, 20, 20};
    cells.lightMm = at(light, 300);
    cells.cameraMm = at(view, 300);
    cells.cells.resize(kSide * kSide);
    placeCellDirections(cells);
    Rgb mean;
    for (int k = 0; k < kSide * kSide; ++k) {
      CellSample& cell = cells.cells[std::size_t(k)];
      cell.value = valueAt(k, toUnitVector(cell.light), toUnitVector(cell.view));
      // 1 % noise, as a bright cell's; or the noise of a dim exposure, the same in every cell.
      cell.variance = noiseSigma > 0.0 ? Rgb::gray(noiseSigma * noiseSigma)
                                       : times(cell.value, cell.value) * 1e-4;
      mean += cell.value * (1.0 / (kSide * kSide));
    }
    FrameSample sample{f * 33000, std::uint64_t(f), light, view, mean};
    sample.cells = std::move(cells);
    bins.add(sample);
  }
  return bins;
}

// A printed pattern: 2 x 2 cell blocks alternating between a warm and a cool ink, every part of
// the BRDF scaled alike; the factors' mean is 1 in every channel.
Rgb printAt(int k) {
  const int i = k % kSide, j = k / kSide;
  return ((i / 2 + j / 2) % 2 == 0) ? Rgb{1.4, 1.0, 0.7} : Rgb{0.6, 1.0, 1.3};
}

const auto kSharpWard = models::makeWard(Rgb::gray(0.02), Rgb::gray(0.9), 0.04, 0.3, 0.0);
const auto kSatin = models::makeWard({0.2, 0.15, 0.1}, Rgb::gray(0.2), 0.15, 0.4, 0.0);

TEST(WindowCellTexture, ASharpLobeOnAPlainMaterialIsReadAsItIs) {
  const AzimuthBins bins = sweep(
      [](int, const UnitVector& l, const UnitVector& v) { return kSharpWard->evaluate(l, v); });
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_EQ(texture.framesUsed, 120);
  EXPECT_EQ(texture.action, CellTextureAction::AsRead) << texture.describe();
  EXPECT_LT(texture.spreadPercent, CellTextureRule{}.textureSpreadPercent / 2);
  EXPECT_THAT(verdictReason(texture), HasSubstr("within the 10 % of a plain material"));
  // The cells' reading is sliceFromCells' own: the lobe the cells caught is not flattened.
  SliceSet set;
  addSweepSlices(set, kDiagonal7575, bins);
  const std::vector<SliceSample> raw = sliceFromCells(bins, kDiagonal7575);
  const SliceSet cellReading = set.cellReading();
  const std::vector<SliceSample>& read = cellReading.slices().front().samples;
  ASSERT_EQ(read.size(), raw.size());
  for (std::size_t b = 0; b < raw.size(); ++b)
    EXPECT_EQ(read[b].value, raw[b].value);
}


TEST(WindowCellTexture, CellsThatScatterFromFrameToFrameAreNotAPattern) {
  // A plain material whose cells' ratios to their frame's mean change from frame to frame by a
  // factor of e (log sigma 1: a sharp lobe that the hand's jitter moves across the window). The
  // median over 120 frames still scatters by 1.25 / sqrt(120) of that, ~11 %, the same at every
  // position: no spot stays brighter than another, and the spread counts only what the medians
  // hold beyond their own scatter.
  std::mt19937 random(11);
  std::normal_distribution<double> jitter(0.0, 1.0);
  const AzimuthBins bins = sweep(
      [&](int, const UnitVector& l, const UnitVector& v) {
        return kSatin->evaluate(l, v) * std::exp(jitter(random));
      },
      SliceKind::Diagonal, 30.0);
  CellTextureRule medianOnly;
  medianOnly.spreadBeyondScatter = false;
  const CellTexture asBefore = cellTextureOf(bins, medianOnly);
  EXPECT_GT(asBefore.spreadPercent, medianOnly.textureSpreadPercent);
  EXPECT_EQ(asBefore.action, CellTextureAction::WindowCentres);
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_LT(texture.spreadPercent, CellTextureRule{}.textureSpreadPercent / 2);
  EXPECT_EQ(texture.action, CellTextureAction::AsRead) << texture.describe();
  // A print under the same scatter is still a print: its factors stay put over the frames.
  const AzimuthBins printed = sweep(
      [&](int k, const UnitVector& l, const UnitVector& v) {
        return times(printAt(k), kSatin->evaluate(l, v)) * std::exp(jitter(random));
      },
      SliceKind::Diagonal, 30.0);
  EXPECT_GT(cellTextureOf(printed).spreadPercent, 25.0);
}

TEST(WindowCellTexture, CellsInTheNoiseAreNotTakenForTexture) {
  // One exposure metered for the sharp Ward's peak: away from it the cells read a few noise
  // sigma either side of the dim diffuse, clamped at 0 as the pipeline clamps them. Their
  // ratios to the frame's mean scatter by orders of magnitude; they are no reading of a spot.
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  const AzimuthBins noisy = sweep(
      [&](int, const UnitVector& l, const UnitVector& v) {
        Rgb value = kSharpWard->evaluate(l, v);
        for (std::size_t c = 0; c < 3; ++c) value[c] = std::max(0.0, value[c] + noise(random));
        return value;
      },
      SliceKind::Diagonal, 75.0, 0.02);
  const CellTexture texture = cellTextureOf(noisy);
  EXPECT_EQ(texture.action, CellTextureAction::AsRead) << texture.describe();
  CellTextureRule everyFrame;
  everyFrame.minCellSnr = 0.0;  // what the noise alone reads as
  EXPECT_GT(cellTextureOf(noisy, everyFrame).spreadPercent, everyFrame.textureSpreadPercent);
}

TEST(WindowCellTexture, AnAlbedoPatternIsFoundAndDividedOut) {
  const AzimuthBins bins = sweep(
      [](int k, const UnitVector& l, const UnitVector& v) {
        return times(printAt(k), kSatin->evaluate(l, v));
      },
      SliceKind::Axial);
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_EQ(texture.action, CellTextureAction::AlbedoNormalised) << texture.describe();
  EXPECT_GT(texture.spreadPercent, 20.0);
  EXPECT_EQ(texture.binsMatched, 24);
  EXPECT_THAT(verdictReason(texture), HasSubstr("that the albedo factors explain"));
  ASSERT_EQ(texture.albedoFactors.size(), std::size_t(kSide * kSide));
  for (int k = 0; k < kSide * kSide; ++k)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(texture.albedoFactors[std::size_t(k)][c], printAt(k)[c], 0.05 * printAt(k)[c])
          << "cell " << k << " channel " << c;
  // Each bin's value from the cells is the material's at the value's directions, not a
  // 0.6-1.4 x texture of whichever cell was nearest the bin centre.
  SliceSet set;
  addSweepSlices(set, kAxial7575, bins);
  const SliceSet cellReading = set.cellReading();
  const std::vector<SliceSample>& fromCells = cellReading.slices().front().samples;
  ASSERT_EQ(fromCells.size(), 24u);
  for (const SliceSample& s : fromCells) {
    const Rgb truth = kSatin->evaluate(toUnitVector(s.light), toUnitVector(s.view));
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(s.value[c], truth[c], 0.08 * truth[c]) << "view azimuth " << s.view.phiDeg;
  }
}

TEST(WindowCellTexture, SpotsThatDifferInTheirLobesGiveTheWindowCentres) {
  // A weave: the print's colours, each spot's broad lobe along its own thread (tangents 0 and
  // 90 deg), on an axial 30/30 sweep where the lobes show: a spot's ratio to the mean follows
  // the directions, and a factor fitted to it misreads the other thread's lobe.
  const auto warp = models::makeWard({0.05, 0.10, 0.32}, {0.18, 0.18, 0.22}, 0.15, 0.8, 0.0);
  const auto weft = models::makeWard({0.34, 0.07, 0.05}, {0.20, 0.15, 0.15}, 0.15, 0.8, 90.0);
  const AzimuthBins bins = sweep(
      [&](int k, const UnitVector& l, const UnitVector& v) {
        return printAt(k)[0] > 1.0 ? warp->evaluate(l, v) : weft->evaluate(l, v);
      },
      SliceKind::Axial, 30.0);
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_EQ(texture.action, CellTextureAction::WindowCentres) << texture.describe();
  EXPECT_GE(texture.binsMatched, texture.binsWithCells / 2);  // not a lack of evidence
  EXPECT_GT(texture.unexplainedPercent, CellTextureRule{}.unexplainedPercent);
  EXPECT_THAT(verdictReason(texture),
              HasSubstr("that the albedo factors do not explain: " +
                        std::to_string(int(std::lround(texture.unexplainedPercent))) +
                        " % left, under 5 % needed"));
  SliceSet set;
  addSweepSlices(set, kAxial3030, bins);
  const std::vector<SliceSample> centres = bins.combine();
  const SliceSet cellReading = set.cellReading();
  const std::vector<SliceSample>& read = cellReading.slices().front().samples;
  ASSERT_EQ(read.size(), centres.size());
  for (std::size_t b = 0; b < read.size(); ++b)
    EXPECT_EQ(read[b].value, centres[b].value);
}

TEST(WindowCellTexture, AFactorShownInFewBinsGivesTheWindowCentres) {
  // The same print on a diagonal sweep: its cells meet at the same directions in 6 bins only,
  // too few to show that the factor holds where the lobe is.
  const AzimuthBins bins = sweep([](int k, const UnitVector& l, const UnitVector& v) {
    return times(printAt(k), kSatin->evaluate(l, v));
  });
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_LT(texture.unexplainedPercent, CellTextureRule{}.unexplainedPercent);
  EXPECT_LT(texture.binsMatched, texture.binsWithCells / 2);
  EXPECT_EQ(texture.action, CellTextureAction::WindowCentres) << texture.describe();
  EXPECT_THAT(verdictReason(texture),
              HasSubstr("shown in " + std::to_string(texture.binsMatched) + " of " +
                        std::to_string(texture.binsWithCells) + " bins only, 50 % needed"));
}

TEST(WindowCellTexture, EveryReasonIsTrueAtItsThresholds) {
  // Verdicts made by hand at the edges of the rule's thresholds: each reason's figures must be
  // on the side of the threshold the verdict says, as printed.
  const CellTextureRule rule;
  CellTexture split;  // 9 frames each clear in some channel, but no channel in 8 of them
  split.framesUsed = 9;
  split.framesInBestChannel = 5;
  EXPECT_THAT(verdictReason(split), HasSubstr(": 5 frames with every cell clear of the noise in "
                                              "a channel, 8 needed"));
  CellTexture plain;
  plain.albedoFactors.assign(64, Rgb::gray(1.0));
  plain.spreadPercent = 9.7;
  EXPECT_THAT(verdictReason(plain), HasSubstr("spread 9.7 %, within the 10 %"));
  CellTexture lone = plain;
  lone.spreadPercent = 10.3;
  lone.action = CellTextureAction::WindowCentres;
  EXPECT_THAT(verdictReason(lone), HasSubstr("(spread 10.3 % over 10 %), and no two cells"));
  CellTexture unexplained = lone;
  unexplained.matchedPairs = 40;
  unexplained.unexplainedPercent = 5.2;
  EXPECT_THAT(verdictReason(unexplained), HasSubstr("do not explain: 5.2 % left, under 5 % needed"));
  CellTexture few = unexplained;
  few.unexplainedPercent = 4.8;
  few.binsMatched = 11;
  few.binsWithCells = 23;
  EXPECT_THAT(verdictReason(few), HasSubstr("shown in 11 of 23 bins only, 50 % needed"));
  CellTexture explained = few;
  explained.binsMatched = 12;
  explained.action = CellTextureAction::AlbedoNormalised;
  EXPECT_THAT(verdictReason(explained), HasSubstr("explain: 4.8 % left over 40 cell pairs in 12 of 23"));
  explained.unexplainedPercent = 4.996;  // not "5 % left" beside "under 5 %"
  EXPECT_THAT(verdictReason(explained), HasSubstr("explain: 4.996 % left"));
  EXPECT_THAT(verdictReason(explained, rule), HasSubstr("(spread 10.3 % over 10 %)"));
}

TEST(WindowCellTexture, TooFewFramesOrAForcedActionAreSaid) {
  AzimuthBins few(SliceKind::Diagonal);
  const AzimuthBins full = sweep([](int k, const UnitVector& l, const UnitVector& v) {
    return times(printAt(k), kSatin->evaluate(l, v));
  });
  for (int f = 0; f < 5; ++f)
    few.add(full.samplesIn(0)[std::size_t(f)]);
  const CellTexture none = cellTextureOf(few);
  EXPECT_EQ(none.action, CellTextureAction::AsRead);
  EXPECT_TRUE(none.albedoFactors.empty());
  EXPECT_NE(none.describe().find("5 frames"), std::string::npos) << none.describe();
  EXPECT_THAT(verdictReason(none),
              HasSubstr("5 frames with every cell clear of the noise in a channel, 8 needed"));
  CellTextureRule forced;
  forced.forced = CellTextureAction::AsRead;
  const CellTexture kept = cellTextureOf(full, forced);
  EXPECT_EQ(kept.action, CellTextureAction::AsRead);
  EXPECT_GT(kept.spreadPercent, 20.0);  // still measured and reported
  EXPECT_THAT(verdictReason(kept, forced), HasSubstr("set by the command line"));
  EXPECT_EQ(parseCellTextureAction("centres"), CellTextureAction::WindowCentres);
  EXPECT_EQ(parseCellTextureAction("mean"), std::nullopt);
}

}  // namespace
}  // namespace slicecap::capture
