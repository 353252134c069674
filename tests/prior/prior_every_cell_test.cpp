// The prior fitted to every window cell (PriorParams::fitEveryCell): one frame's cells weigh one
// sample between them, shared by their noise, however many they are.
#include <gtest/gtest.h>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_model.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::prior {
namespace {

const SliceId kAxial3030{SliceKind::Axial, {30, 30}};

// The ideal slices of a satin; every sample also a frame of one cell (variance 0), but the
// axial 30/30 slice's first, whose frame is `bright` (copies of that cell at 3 x its value and
// variance `variance`) plus `dim` (copies at its value, variance `dimVariance`).
SliceSet withCellFrames(const SliceSet& ideal, int bright, double variance, int dim = 0,
                        double dimVariance = 0.0, bool eachItsOwnFrame = false) {
  SliceSet out;
  for (const Slice& s : ideal.slices()) {
    for (const SliceSample& sample : s.samples) out.add(s.id, sample);
    for (std::size_t k = 0; k < s.samples.size(); ++k) {
      const SliceSample& sample = s.samples[k];
      if (s.id != kAxial3030 || k != 0) {
        out.addCellFrame(s.id, {{sample, Rgb{}}});
        continue;
      }
      FrameCellPoints frame;
      for (int i = 0; i < bright; ++i)
        frame.push_back({{sample.light, sample.view, sample.value * 3.0}, Rgb::gray(variance)});
      for (int i = 0; i < dim; ++i)
        frame.push_back({sample, Rgb::gray(dimVariance)});
      if (!eachItsOwnFrame) {
        out.addCellFrame(s.id, frame);
        continue;
      }
      for (const CellPoint& cell : frame) out.addCellFrame(s.id, {cell});
    }
  }
  return out;
}

double apart(const Abrdf& a, const Abrdf& b) { return eval::compare(a, b).deltaE; }

TEST(PriorEveryCell, AFramesCellsWeighOneSampleHoweverManyTheyAre) {
  const Abrdf truth = models::tabulate(
      *models::makeWard({0.04, 0.08, 0.3}, {0.15, 0.15, 0.18}, 0.12, 0.45, 45.0));
  const SliceSet ideal = recon::extractSlices(truth);
  PriorParams everyCell;
  everyCell.fitEveryCell = true;
  const PriorModel& model = defaultPriorModel();
  // Each sample a frame of one cell, the first three times too bright.
  PriorReport report;
  const Abrdf fromOneBrightCell =
      reconstructWithPrior(withCellFrames(ideal, 1, 0.0), model, everyCell, &report);
  EXPECT_EQ(report.frameGroups, ideal.sampleCount());
  // One frame of 64 copies of the bright cell: the weight of one.
  const Abrdf fromOneFrame = reconstructWithPrior(withCellFrames(ideal, 64, 0.0), model, everyCell);
  EXPECT_LT(apart(fromOneFrame, fromOneBrightCell), 1e-3);
  // The same 64 as 64 frames outvote the rest: far from it.
  const Abrdf fromFrames =
      reconstructWithPrior(withCellFrames(ideal, 64, 0.0, 0, 0.0, true), model, everyCell);
  EXPECT_GT(apart(fromFrames, fromOneBrightCell), 100.0 * apart(fromOneFrame, fromOneBrightCell));
  // Without fitEveryCell the cell frames are not read.
  EXPECT_LT(apart(reconstructWithPrior(withCellFrames(ideal, 64, 0.0), model),
                  reconstructWithPrior(ideal, model)),
            1e-6);
}

TEST(PriorEveryCell, WithinAFrameTheQuieterCellsWeighMore) {
  const Abrdf truth = models::tabulate(
      *models::makeWard({0.04, 0.08, 0.3}, {0.15, 0.15, 0.18}, 0.12, 0.45, 45.0));
  const SliceSet ideal = recon::extractSlices(truth);
  PriorParams everyCell;
  everyCell.fitEveryCell = true;
  const PriorModel& model = defaultPriorModel();
  const Abrdf truthFrame = reconstructWithPrior(withCellFrames(ideal, 0, 0.0, 1), model, everyCell);
  const Abrdf brightFrame = reconstructWithPrior(withCellFrames(ideal, 1, 0.0), model, everyCell);
  ASSERT_GT(apart(truthFrame, brightFrame), 0.01);
  // A frame of 8 bright cells in the noise (sigma 50 x the value) and 8 quiet true ones reads
  // as the true ones.
  const double value = ideal.find(kAxial3030)->samples.front().value.mean();
  const Abrdf mixed = reconstructWithPrior(
      withCellFrames(ideal, 8, 2500.0 * value * value, 8, 0.0), model, everyCell);
  EXPECT_LT(apart(mixed, truthFrame), 0.05 * apart(truthFrame, brightFrame));
}

}  // namespace
}  // namespace slicecap::prior
