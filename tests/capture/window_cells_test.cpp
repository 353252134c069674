// The window's cells: their directions from the geometry, and a slice valued from the cells
// nearest each bin centre (a peak the window centre missed is caught by the cell that saw it).
#include "slicecap/capture/window_cells.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "slicecap/capture/capture_error.hpp"

namespace slicecap::capture {
namespace {

const SliceId kDiagonal7575{SliceKind::Diagonal, {75, 75}};

// Directions worked out by hand: cell 0 of a 2 x 2 grid over [-10, 10] mm sits at (-5, -5); the
// light at (0, 0, 100) is along (5, 5, 100) from it: theta = atan(sqrt(50) / 100) = 4.0447 deg,
// phi = 45; the camera at (100, 0, 100) along (105, 5, 100): theta = atan(105.119 / 100) =
// 46.4296, phi = atan(5 / 105) = 2.7263. Cell 1 at (5, -5): light (-5, 5, 100), 4.0447 / 135;
// camera (95, 5, 100), 43.5708 / 3.0128.
TEST(WindowCells, DirectionsFromTheCellCentreToTheLightAndTheCamera) {
  WindowCells cells;
  cells.cellsPerSide = 2;
  cells.gridMm = {-10, -10, 10, 10};
  cells.lightMm = {0, 0, 100};
  cells.cameraMm = {100, 0, 100};
  cells.cells.resize(4);
  placeCellDirections(cells);
  EXPECT_EQ(cellCentreMm(cells, 0), (std::array<double, 2>{-5, -5}));
  EXPECT_EQ(cellCentreMm(cells, 3), (std::array<double, 2>{5, 5}));
  EXPECT_NEAR(cells.cells[0].light.thetaDeg, 4.0447, 1e-4);
  EXPECT_NEAR(cells.cells[0].light.phiDeg, 45.0, 1e-9);
  EXPECT_NEAR(cells.cells[0].view.thetaDeg, 46.4296, 1e-4);
  EXPECT_NEAR(cells.cells[0].view.phiDeg, 2.7263, 1e-4);
  EXPECT_NEAR(cells.cells[1].light.thetaDeg, 4.0447, 1e-4);
  EXPECT_NEAR(cells.cells[1].light.phiDeg, 135.0, 1e-9);
  EXPECT_NEAR(cells.cells[1].view.thetaDeg, 43.5708, 1e-4);
  EXPECT_NEAR(cells.cells[1].view.phiDeg, 3.0128, 1e-4);
  cells.cells.resize(3);
  EXPECT_THROW(placeCellDirections(cells), capture::CaptureError);
}

TEST(WindowCells, ValuesAreKeptAtFloatPrecision) {
  EXPECT_EQ(cellPrecision(0.1), 0.1);  // the double nearest "0.1", not float(0.1)'s
  EXPECT_EQ(cellPrecision(1.0 / 3.0), 0.33333334);
  EXPECT_NE(cellPrecision(1.0 / 3.0), 1.0 / 3.0);
}

// A diagonal 75/75 frame whose window centre sits at view azimuth `centrePhiDeg` and reads
// `centreValue`, with cells at the given view azimuths (light opposite) and values.
struct CellSpec {
  double viewPhiDeg;
  double value;
  bool clipped = false;
  double variance = 1e-4;
};

FrameSample frameWithCells(double centrePhiDeg, double centreValue,
                           const std::vector<CellSpec>& specs, std::uint64_t frame) {
  FrameSample s{std::int64_t(frame) * 33000, frame, {75, 360 - centrePhiDeg},
                {75, centrePhiDeg},            Rgb::gray(centreValue)};
  WindowCells cells;
  cells.cellsPerSide = 1;  // the rule reads the cells' directions, not the grid
  for (const CellSpec& c : specs)
    cells.cells.push_back({{75, 360 - c.viewPhiDeg},
                           {75, c.viewPhiDeg},
                           Rgb::gray(c.value),
                           Rgb::gray(c.variance),
                           c.clipped});
  s.cells = std::move(cells);
  return s;
}

TEST(WindowCells, ASliceValueComesFromTheCellNearestTheBinCentre) {
  // The 75/75 mirror peak at view azimuth 90 (a bin centre): two frames land 2 deg either side,
  // their centres read the lobe's tail; one frame's edge cell is 0.1 deg off the peak, another's
  // 0.2 deg off (both seeing it), a third cell nearer still is clipped (an HDR long exposure).
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(frameWithCells(88.0, 0.1, {{88.0, 0.1}, {89.9, 5.0}, {90.05, 9.0, true}}, 1));
  bins.add(frameWithCells(92.0, 0.1, {{92.0, 0.1}, {90.2, 4.0, false, 4e-4}}, 2));
  const std::vector<SliceSample> centres = bins.combine();
  ASSERT_EQ(centres.size(), 1u);
  EXPECT_NEAR(centres[0].value.r(), 0.1, 1e-12);  // the window centres missed the peak
  const std::vector<SliceSample> fromCells = sliceFromCells(bins, kDiagonal7575);
  // Bins 6 (90 deg): the cells at 89.9 and 90.2 (0.3 apart in view, 0.42 in both) pooled,
  // inverse-variance weighted: (5 / 1e-4 + 4 / 4e-4) / (1 / 1e-4 + 1 / 4e-4) = 4.8; the clipped
  // cell left out.
  ASSERT_EQ(fromCells.size(), 1u);
  EXPECT_NEAR(fromCells[0].value.r(), 4.8, 1e-9);
  EXPECT_NEAR(fromCells[0].view.phiDeg, 89.96, 0.01);
  // With a wider pool the centres' cells at 88 and 92 join in: the tolerance keeps them out.
  EXPECT_LT(sliceFromCells(bins, kDiagonal7575, {5.0}).front().value.r(), 4.0);
}

TEST(WindowCells, CellsCanGiveASamplePerStretchOfTheSliceNotPerBin) {
  // A lobe narrower than a bin: frames at 84 and 96 deg, their cells from 83 to 97, all in bin 6
  // (82.5-97.5). Per bin the reading is the cell nearest 90 deg, the lobe's top as a one-bin
  // spike; every 3 deg of the cells' own view azimuth it keeps the flanks.
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(frameWithCells(84.0, 0.2, {{83.0, 0.1}, {84.0, 0.2}, {86.0, 1.0}, {88.4, 3.0}}, 1));
  bins.add(frameWithCells(96.0, 0.2, {{89.9, 5.0}, {92.0, 2.0}, {95.5, 0.4}, {97.0, 0.15}}, 2));
  EXPECT_EQ(sliceFromCells(bins, kDiagonal7575).size(), 1u);
  CellSliceRule every3;
  every3.pointsEveryDeg = 3.0;
  const std::vector<SliceSample> fromCells = sliceFromCells(bins, kDiagonal7575, every3);
  // By 3 deg, each stretch read as a bin is, from the cell nearest its centre: [81, 84) 83;
  // [84, 87) 86; [87, 90) 88.4 (3, not pooled with the 5 at 89.9: 1.5 deg apart); [90, 93) 92;
  // [93, 96) 95.5; [96, 99) 97.
  ASSERT_EQ(fromCells.size(), 6u);
  const double expectedPhiDeg[] = {83.0, 86.0, 88.4, 92.0, 95.5, 97.0};
  for (std::size_t k = 0; k < fromCells.size(); ++k)
    EXPECT_NEAR(fromCells[k].view.phiDeg, expectedPhiDeg[k], 1e-9) << k;
  EXPECT_NEAR(fromCells[2].value.r(), 3.0, 1e-12);
  every3.pointsEveryDeg = -1.0;
  EXPECT_THROW(sliceFromCells(bins, kDiagonal7575, every3), capture::CaptureError);
}

TEST(WindowCells, ACellFillsABinNoWindowCentreFellIn) {
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(frameWithCells(95.0, 0.5, {{95.0, 0.5}, {103.0, 0.7}}, 1));
  EXPECT_EQ(bins.filledCount(), 1);
  const std::vector<SliceSample> fromCells = sliceFromCells(bins, kDiagonal7575);
  ASSERT_EQ(fromCells.size(), 2u);  // bins 6 (the centre's cell) and 7 (105 deg: the edge cell)
  EXPECT_NEAR(fromCells[1].view.phiDeg, 103.0, 1e-9);
  EXPECT_NEAR(fromCells[1].value.r(), 0.7, 1e-12);
}

TEST(WindowCells, ABinOfClippedCellsOrFramesWithoutCellsKeepsItsCentres) {
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(frameWithCells(90.0, 0.3, {{90.0, 9.0, true}}, 1));
  FrameSample old{0, 2, {75, 330}, {75, 30}, Rgb::gray(0.25)};  // a record from before cells
  bins.add(old);
  const std::vector<SliceSample> fromCells = sliceFromCells(bins, kDiagonal7575);
  ASSERT_EQ(fromCells.size(), 2u);
  EXPECT_NEAR(fromCells[0].value.r(), 0.25, 1e-12);  // bin 2 (30 deg): the old frame's centre
  EXPECT_NEAR(fromCells[1].value.r(), 0.3, 1e-12);   // bin 6: the centre, its cell clipped
  EXPECT_THROW(sliceFromCells(bins, {SliceKind::Point, {75, 75}}), capture::CaptureError);
}

TEST(WindowCells, ASweepsSlicesCarryCellSamplesOnlyWhenItsFramesHaveCells) {
  AzimuthBins withCells(SliceKind::Diagonal), without(SliceKind::Diagonal);
  withCells.add(frameWithCells(88.0, 0.1, {{89.9, 5.0}}, 1));
  without.add(FrameSample{0, 1, {75, 272}, {75, 88}, Rgb::gray(0.1)});
  SliceSet set;
  addSweepSlices(set, kDiagonal7575, withCells);
  addSweepSlices(set, {SliceKind::Diagonal, {30, 30}}, without);
  ASSERT_EQ(set.slices().size(), 2u);
  const Slice& diagonal3030 = set.slices()[0];
  const Slice& diagonal7575 = set.slices()[1];
  EXPECT_TRUE(diagonal3030.cellSamples.empty());
  ASSERT_EQ(diagonal7575.cellSamples.size(), 1u);
  EXPECT_NEAR(diagonal7575.samples[0].value.r(), 0.1, 1e-12);
  EXPECT_NEAR(diagonal7575.cellSamples[0].value.r(), 5.0, 1e-12);
  // The cell reading: cell samples where a slice has them, its samples elsewhere.
  const SliceSet reading = set.cellReading();
  EXPECT_NEAR(reading.slices()[1].samples[0].value.r(), 5.0, 1e-12);
  EXPECT_NEAR(reading.slices()[0].samples[0].value.r(), 0.1, 1e-12);
  EXPECT_FALSE(reading.hasCellSamples());
  EXPECT_TRUE(set.hasCellSamples());
}

TEST(WindowCells, EveryUsableCellIsAPointInItsFramesGroup) {
  // Frame 1: two usable cells and a clipped one; frame 2: one cell; an old frame without cells in
  // a bin no cell reaches keeps its centre, a group of one with no noise.
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(frameWithCells(88.0, 0.1, {{88.0, 0.1}, {89.9, 5.0, false, 4e-4}, {90.05, 9.0, true}}, 1));
  bins.add(frameWithCells(92.0, 0.2, {{92.0, 0.2}}, 2));
  bins.add(FrameSample{0, 3, {75, 330}, {75, 30}, Rgb::gray(0.25)});
  const std::vector<FrameCellPoints> groups = cellPointsByFrame(bins, SliceKind::Diagonal);
  ASSERT_EQ(groups.size(), 3u);
  ASSERT_EQ(groups[0].size(), 2u);
  EXPECT_NEAR(groups[0][1].sample.value.r(), 5.0, 1e-12);
  EXPECT_NEAR(groups[0][1].variance.r(), 4e-4, 1e-12);
  EXPECT_EQ(groups[1].size(), 1u);
  ASSERT_EQ(groups[2].size(), 1u);
  EXPECT_NEAR(groups[2][0].sample.value.r(), 0.25, 1e-12);
  EXPECT_EQ(groups[2][0].variance.r(), 0.0);
  // A sweep's slice carries them, and its cells' reading keeps them.
  SliceSet set;
  addSweepSlices(set, kDiagonal7575, bins);
  EXPECT_EQ(set.find(kDiagonal7575)->cellFrames.size(), 3u);
  EXPECT_TRUE(set.cellReading().hasCellFrames());
}

}  // namespace
}  // namespace slicecap::capture
