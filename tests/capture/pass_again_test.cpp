// The bins of a sweep to pass again: left empty, or next to a lobe no window's cell reached.
#include "slicecap/capture/pass_again.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "../support/window_cells_sweep.hpp"
#include "slicecap/capture/capture_error.hpp"

namespace slicecap::capture {
namespace {

const SliceId kDiagonal7575{SliceKind::Diagonal, {75, 75}};

using test::lobe;
using test::Print;
using test::Profile;

// The frames of test::diagonalSweep in their bins.
AzimuthBins sweep(const Profile& profile, double fromDeg, double toDeg,
                  const std::vector<std::pair<double, double>>& skipped,
                  const Print& print = [](int) { return 1.0; }) {
  AzimuthBins bins(SliceKind::Diagonal);
  for (const FrameSample& frame : test::diagonalSweep(profile, fromDeg, toDeg, skipped, print))
    bins.add(frame);
  return bins;
}

std::vector<std::pair<double, PassAgainReason>> named(const std::vector<PassAgainBin>& bins) {
  std::vector<std::pair<double, PassAgainReason>> out;
  for (const PassAgainBin& b : bins) {
    EXPECT_EQ(b.slice, kDiagonal7575);
    EXPECT_DOUBLE_EQ(b.azimuthDeg, 15.0 * b.bin);
    out.emplace_back(b.azimuthDeg, b.reason);
  }
  return out;
}

TEST(PassAgain, NamesEmptyBinsAndAPeakTheCellsRiseTowardButNoneReached) {
  // Two sharp lobes (sigma 1.5 deg): at 180 the frames pass over it, at 90 they skip 86-94 deg,
  // so the nearest cells are 2.8 deg of the parameter (~3.8 deg of light and view) short of it
  // on either side, and still rising. No frame between 198 and 243: bins 210 and 225 empty.
  const Profile sharp = [](double p) { return 0.1 + lobe(p, 90, 1.5) + lobe(p, 180, 1.5); };
  const AzimuthBins bins = sweep(sharp, 0, 357, {{86, 94}, {198, 243}});
  using R = PassAgainReason;
  const std::vector<std::pair<double, R>> expected{
      {90, R::PeakNotReached}, {210, R::Empty}, {225, R::Empty}};
  EXPECT_EQ(named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished)), expected);
  // A plain material: the texture verdict reads its cells as they are, and the peak is named.
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_EQ(texture.action, CellTextureAction::AsRead) << texture.describe();
  EXPECT_EQ(named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished, {}, texture)),
            expected);
  // The gap is what names it: with the centre counted as reached 5 deg away it is not named.
  PassAgainRule lenient;
  lenient.reachedWithinDeg = 5.0;
  EXPECT_EQ(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished, lenient).size(), 2u);
  EXPECT_EQ(toString(R::PeakNotReached), "peak_not_reached");
  EXPECT_EQ(toString(R::Empty), "empty");
}

TEST(PassAgain, AThreadsColourAtTheWindowsEdgeIsNoMissedPeak) {
  // A plain diffuse material under a weave whose bright thread lies under the window's two
  // outer cells (3 x the others). Before the 86-94 gap the edge cells read 3 x those behind
  // them, a sharp peak's rise when read as they are; but it is the same in every frame, so
  // the texture verdict divides it out or drops the cells, and no peak is named.
  const Profile flat = [](double) { return 1.0; };
  const AzimuthBins bins = sweep(flat, 0, 357, {{86, 94}, {198, 243}},
                                 [](int k) { return std::abs(k) == 4 ? 3.0 : 1.0; });
  using R = PassAgainReason;
  const std::vector<std::pair<double, R>> empties{{210, R::Empty}, {225, R::Empty}};
  const std::vector<std::pair<double, R>> asRead =
      named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished));
  EXPECT_NE(std::find(asRead.begin(), asRead.end(), std::pair{90.0, R::PeakNotReached}),
            asRead.end());
  const CellTexture texture = cellTextureOf(bins);
  EXPECT_NE(texture.action, CellTextureAction::AsRead) << texture.describe();
  EXPECT_EQ(named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished, {}, texture)),
            empties)
      << texture.describe();
  // Window centres: no cell is evidence of a missed peak; the empty bins are still named.
  CellTexture centres = texture;
  centres.action = CellTextureAction::WindowCentres;
  EXPECT_EQ(named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished, {}, centres)),
            empties);
}

TEST(PassAgain, WhileATexturedSweepRunsAThreadsColourIsNoMissedPeak) {
  // The woven window of the test above, swept from 0 to 180 deg so far past the 86-94 gap, its
  // frames judged as they come: the running sweep's cells are read as its verdict says, as a
  // finished one's are, and the edge cells' thread is not named a peak the sweep missed.
  const Profile flat = [](double) { return 1.0; };
  const Print thread = [](int k) { return std::abs(k) == 4 ? 3.0 : 1.0; };
  AzimuthBins bins(SliceKind::Diagonal);
  RunningCellTexture running;
  int judgements = 0;
  for (const FrameSample& frame : test::diagonalSweep(flat, 0, 180, {{86, 94}}, thread)) {
    bins.add(frame);
    const std::size_t before = running.framesJudged();
    running.of(bins);
    judgements += running.framesJudged() != before ? 1 : 0;
  }
  const CellTexture& texture = running.of(bins);
  EXPECT_NE(texture.action, CellTextureAction::AsRead) << texture.describe();
  const std::pair<double, PassAgainReason> thread90{90.0, PassAgainReason::PeakNotReached};
  const auto asRead = named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Running));
  EXPECT_NE(std::find(asRead.begin(), asRead.end(), thread90), asRead.end());
  EXPECT_TRUE(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Running, {}, texture).empty())
      << texture.describe();
  // Judged again as the frames grow by a quarter, not on each of the 58 frames: the verdict is
  // never older than the last fifth of them.
  EXPECT_GT(1.25 * double(running.framesJudged()), 58.0);
  EXPECT_LT(judgements, 20);
  // The slice redone: the verdict is judged again from its new frames, none yet.
  EXPECT_EQ(running.of(AzimuthBins(SliceKind::Diagonal)).framesUsed, 0);
  EXPECT_EQ(running.framesJudged(), 0u);
}

TEST(PassAgain, ARedoneSweepIsJudgedAfreshThoughItsFramesRegrewUnasked) {
  // The woven sweep judged, then redone on a plain window with no verdict asked while its frames
  // came back to as many as before (fewer than a quarter more): the kept verdict is the old
  // run's, and the new run's is its own.
  const Profile flat = [](double) { return 1.0; };
  const Print thread = [](int k) { return std::abs(k) == 4 ? 3.0 : 1.0; };
  AzimuthBins bins(SliceKind::Diagonal);
  for (const FrameSample& frame : test::diagonalSweep(flat, 0, 180, {{86, 94}}, thread))
    bins.add(frame);
  RunningCellTexture running;
  ASSERT_NE(running.of(bins).action, CellTextureAction::AsRead);
  const std::size_t judged = running.framesJudged();
  bins.clear();
  for (const FrameSample& frame : test::diagonalSweep(flat, 0, 180, {{86, 94}}))
    bins.add(frame);
  const CellTexture& redone = running.of(bins);
  EXPECT_EQ(running.framesJudged(), judged);
  EXPECT_EQ(redone.action, CellTextureAction::AsRead) << redone.describe();
  // Adding frames keeps the run; clearing starts another.
  const std::uint64_t run = bins.run();
  bins.add(test::diagonalSweep(flat, 200, 203, {}).front());
  EXPECT_EQ(bins.run(), run);
  bins.clear();
  EXPECT_NE(bins.run(), run);
}

TEST(PassAgain, ABroadLobeWithTheSameGapIsNotAMissedPeak) {
  // sigma 15 deg: over the last two cell steps before the gap it changes by a few per cent.
  const Profile broad = [](double p) { return 0.1 + lobe(p, 90, 15); };
  const AzimuthBins bins = sweep(broad, 0, 357, {{86, 94}});
  EXPECT_TRUE(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished).empty());
}

TEST(PassAgain, WhileTheSweepRunsTheBinsAheadOfItAreNotYetMissed) {
  // Swept from 0 to 180 so far, skipping 50-70: bin 60 is a gap behind the sweep, 195-345 lie
  // ahead of it.
  const Profile flat = [](double) { return 0.1; };
  const AzimuthBins bins = sweep(flat, 0, 180, {{50, 70}});
  using R = PassAgainReason;
  EXPECT_EQ(named(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Running)),
            (std::vector<std::pair<double, R>>{{60, R::Empty}}));
  EXPECT_EQ(binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished).size(), 12u);
  EXPECT_TRUE(binsToPassAgain(AzimuthBins(SliceKind::Diagonal), kDiagonal7575,
                              SweepProgress::Finished)
                  .empty());
  EXPECT_THROW(binsToPassAgain(bins, SliceId{SliceKind::Point, {0, 0}}, SweepProgress::Running),
               capture::CaptureError);
}

TEST(PassAgain, ACellInTheBinIsEnoughToFillIt) {
  // No frame's centre in bin 60 (52.5-67.5), but the frame at 70.5 has cells down to 67.3 deg:
  // the slice value reads them, so the bin is not empty.
  const Profile flat = [](double) { return 0.1; };
  AzimuthBins bins(SliceKind::Diagonal);
  bins.add(test::diagonalFrameAt(49, flat, 1));
  bins.add(test::diagonalFrameAt(70.5, flat, 2));
  const std::vector<PassAgainBin> out = binsToPassAgain(bins, kDiagonal7575, SweepProgress::Finished);
  for (const PassAgainBin& b : out) EXPECT_NE(b.bin, 4);
  EXPECT_TRUE(bins.samplesIn(4).empty());
}

}  // namespace
}  // namespace slicecap::capture
