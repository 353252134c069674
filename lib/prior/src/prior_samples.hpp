// The prior's samples as design rows: where each reads the table, its half-vector terms, its
// cos-weighted value, and the table entries all rows read, gathered once.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "half_vector_terms.hpp"
#include "slicecap/core/grid_interpolation.hpp"
#include "slicecap/core/rgb.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {

/// \brief One sample as the fit reads it.
struct SampleRow {
  std::vector<TableTap> taps;  ///< isotropicTableTaps: where the basis and mean are read
  std::vector<int> slots;      ///< per tap, its entry's row in TappedEntries
  HalfVectorTerms terms;       ///< the half-vector terms at the sample's own directions
  Rgb weighted;                ///< value times cos(theta_i) cos(theta_v), clipped at 0
  const SliceId* slice;
  double parameterDeg;
  Rgb weightedVariance{};  ///< of `weighted` (a cell's noise times the cos weight squared)
  int frame = -1;          ///< the frame group of a cell point (gatherCellRows); -1: none
};

/// \brief Every sample of `slices` as a row (they point into `slices`, which must outlive them),
/// read at its measured angles or through the table's interpolation (PriorParams::
/// readAtMeasuredAngles). Throws recon::ReconstructionError naming the slice for a sample off the
/// hemisphere or a non-finite value, and when there are no samples.
std::vector<SampleRow> gatherSampleRows(const SliceSet& slices, bool readAtMeasuredAngles);

/// \brief The rows of a fit of every cell: each slice's cell frames (Slice::cellFrames), every
/// cell a row with its frame's group number (0, 1, ...) and its noise; a slice without cell
/// frames gives its samples as gatherSampleRows does (no group). Throws as gatherSampleRows.
std::vector<SampleRow> gatherCellRows(const SliceSet& slices, bool readAtMeasuredAngles);

/// \brief The number of frame groups of `rows` (the largest group number + 1).
int frameGroupCount(const std::vector<SampleRow>& rows);

/// \brief The floor of the log map per channel, relative to the largest sample (as in training).
Rgb logFloor(const std::vector<SampleRow>& rows, double floorFraction);

/// \brief The natural log of the largest cos-weighted sample over the median one (luminance, the
/// mean of the channels): how much directional structure the samples show. Infinite when the
/// median is 0.
double sampleDynamicRangeLog(const std::vector<SampleRow>& rows);

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// \brief The distinct table entries the samples' taps read, and the design's columns at each (the
/// basis components), gathered once. Off the grid (every jittered sample, every texel of a BTF) a
/// sample reads up to 16 entries and its neighbours along the slice read most of the same ones;
/// and the basis is stored component by component, so gathering one entry's features touches 16
/// cache lines. Everything computed per entry (the features, the fitted log values and their
/// exponentials) is computed once per entry here, then blended per tap.
struct TappedEntries {
  std::vector<int> entries;  ///< slot -> table entry (light * 81 + view)
  RowMajorMatrix features;   ///< slot x components
};

/// \brief Fills every row's `slots` and gathers the entries. `basisByEntry`: the basis entry by
/// entry (PriorReconstructor), or null to read it from the model.
TappedEntries gatherTappedEntries(std::vector<SampleRow>& rows, const PriorModel& model,
                                  const float* basisByEntry);

/// \brief The log values of the fitted model at each sample's taps (basis and mean, per slot) and,
/// per row, its half-vector part at the sample's own directions: the model at a sample is
/// sum_t w_t exp(slotLog_t + rowLog).
struct SampleModel {
  std::vector<Eigen::Array3d> slotLog;  ///< per slot: mean + basis c
  std::vector<Eigen::Array3d> rowLog;   ///< per row: half-vector terms d
};

/// \brief The model of `coefficients` (components, then half-vector terms; x 3) at the rows.
SampleModel sampleModel(const std::vector<SampleRow>& rows, const TappedEntries& tapped,
                        const PriorModel& model, const Eigen::MatrixXd& coefficients);

}  // namespace slicecap::prior
