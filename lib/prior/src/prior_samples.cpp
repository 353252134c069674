// The prior's samples as design rows, and the fitted model read back at them.
#include "prior_samples.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "isotropic_taps.hpp"
#include "slicecap/core/core_error.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/recon/errors.hpp"

namespace slicecap::prior {
namespace {

// Where the sample reads the table and its half-vector terms; see
// PriorParams::readAtMeasuredAngles.
void readDirections(SampleRow& row, const SliceSample& s, bool readAtMeasuredAngles) {
  if (readAtMeasuredAngles) {
    row.taps = isotropicTableTaps(s.light, s.view);
    row.terms = halfVectorTerms(toUnitVector(s.light), toUnitVector(s.view));
    return;
  }
  row.taps = tableTaps(s.light, s.view);
  for (const TableTap& tap : row.taps) {
    const HalfVectorTerms& entryTerms =
        gridHalfVectorTerms()[std::size_t(tap.light * 81 + tap.view)];
    for (int j = 0; j < kHalfVectorTermCount; ++j)
      row.terms[std::size_t(j)] += tap.weight * entryTerms[std::size_t(j)];
  }
}

}  // namespace

namespace {

// One sample of `slice` as a row; `variance` the variance of its value.
SampleRow sampleRow(const Slice& slice, const SliceSample& s, const Rgb& variance,
                    bool readAtMeasuredAngles) {
  SampleRow row{{}, {}, {}, {}, &slice.id, sliceParameterDeg(slice.id.kind, s)};
  try {
    readDirections(row, s, readAtMeasuredAngles);
  } catch (const CoreError& e) {
    throw recon::ReconstructionError("slice " + toString(slice.id) + ": " + e.what());
  }
  // The cos weighting the table's entries carry, read through the same taps: the sample is
  // the taps' blend of f, so weighting it by its own angles' cosines would put a bias of up
  // to 20 % on every jittered sample near 75 deg (cos 78 / cos 75) into the fit and the kept
  // residuals.
  double cc = 0.0;
  for (const TableTap& tap : row.taps)
    cc += tap.weight * bonn::cosines()[tap.light] * bonn::cosines()[tap.view];
  for (std::size_t c = 0; c < 3; ++c) {
    if (!std::isfinite(s.value[c]) || !std::isfinite(variance[c]))
      throw recon::ReconstructionError("slice " + toString(slice.id) + ": non-finite sample");
    row.weighted[c] = std::max(0.0, s.value[c]) * cc;
    row.weightedVariance[c] = std::max(0.0, variance[c]) * cc * cc;
  }
  return row;
}

}  // namespace

std::vector<SampleRow> gatherSampleRows(const SliceSet& slices, bool readAtMeasuredAngles) {
  std::vector<SampleRow> rows;
  rows.reserve(slices.sampleCount());
  for (const Slice& slice : slices.slices())
    for (const SliceSample& s : slice.samples)
      rows.push_back(sampleRow(slice, s, Rgb{}, readAtMeasuredAngles));
  if (rows.empty()) throw recon::ReconstructionError("the prior needs at least one sample");
  return rows;
}

std::vector<SampleRow> gatherCellRows(const SliceSet& slices, bool readAtMeasuredAngles) {
  std::vector<SampleRow> rows;
  int frame = 0;
  for (const Slice& slice : slices.slices()) {
    if (slice.cellFrames.empty()) {
      for (const SliceSample& s : slice.samples)
        rows.push_back(sampleRow(slice, s, Rgb{}, readAtMeasuredAngles));
      continue;
    }
    for (const FrameCellPoints& cells : slice.cellFrames) {
      for (const CellPoint& cell : cells) {
        rows.push_back(sampleRow(slice, cell.sample, cell.variance, readAtMeasuredAngles));
        rows.back().frame = frame;
      }
      ++frame;
    }
  }
  if (rows.empty()) throw recon::ReconstructionError("the prior needs at least one sample");
  return rows;
}

int frameGroupCount(const std::vector<SampleRow>& rows) {
  int count = 0;
  for (const SampleRow& r : rows)
    count = std::max(count, r.frame + 1);
  return count;
}

Rgb logFloor(const std::vector<SampleRow>& rows, double floorFraction) {
  Rgb floor;
  for (const SampleRow& r : rows) {
    for (std::size_t c = 0; c < 3; ++c)
      floor[c] = std::max(floor[c], r.weighted[c]);
  }
  for (std::size_t c = 0; c < 3; ++c)
    floor[c] = std::max(floor[c] * floorFraction, std::numeric_limits<double>::min());
  return floor;
}

double sampleDynamicRangeLog(const std::vector<SampleRow>& rows) {
  std::vector<double> luminance;
  luminance.reserve(rows.size());
  for (const SampleRow& r : rows)
    luminance.push_back((r.weighted[0] + r.weighted[1] + r.weighted[2]) / 3.0);
  const auto middle = luminance.begin() + static_cast<std::ptrdiff_t>(luminance.size() / 2);
  std::nth_element(luminance.begin(), middle, luminance.end());
  const double median = *middle;
  const double largest = *std::max_element(luminance.begin(), luminance.end());
  if (!(median > 0.0)) return std::numeric_limits<double>::infinity();
  return std::log(largest / median);
}

TappedEntries gatherTappedEntries(std::vector<SampleRow>& rows, const PriorModel& model,
                                  const float* basisByEntry) {
  TappedEntries out;
  std::vector<int> slotOf(kFeatureCount, -1);
  for (SampleRow& r : rows) {
    r.slots.resize(r.taps.size());
    for (std::size_t t = 0; t < r.taps.size(); ++t) {
      const int entry = r.taps[t].light * 81 + r.taps[t].view;
      if (slotOf[entry] < 0) {
        slotOf[entry] = static_cast<int>(out.entries.size());
        out.entries.push_back(entry);
      }
      r.slots[t] = slotOf[entry];
    }
  }
  const int k = model.components();
  const int slots = static_cast<int>(out.entries.size());
  out.features.resize(slots, k);
  if (basisByEntry) {
    for (int s = 0; s < slots; ++s) {
      const float* entryBasis = basisByEntry + std::size_t(out.entries[std::size_t(s)]) * k;
      for (int j = 0; j < k; ++j)
        out.features(s, j) = entryBasis[j];
    }
  } else {
    for (int j = 0; j < k; ++j) {
      const float* component = model.component(j);
      for (int s = 0; s < slots; ++s)
        out.features(s, j) = component[out.entries[std::size_t(s)]];
    }
  }
  return out;
}

SampleModel sampleModel(const std::vector<SampleRow>& rows, const TappedEntries& tapped,
                        const PriorModel& model, const Eigen::MatrixXd& coefficients) {
  const int k = static_cast<int>(tapped.features.cols());
  const int terms = static_cast<int>(coefficients.rows()) - k;
  SampleModel out;
  out.slotLog.resize(tapped.entries.size());
  for (std::size_t s = 0; s < tapped.entries.size(); ++s) {
    out.slotLog[s] =
        (tapped.features.row(Eigen::Index(s)) * coefficients.topRows(k)).transpose().array() +
        double(model.mean[std::size_t(tapped.entries[s])]);
  }
  out.rowLog.assign(rows.size(), Eigen::Array3d::Zero());
  if (terms > 0) {
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Eigen::Map<const Eigen::RowVectorXd> rowTerms(rows[i].terms.data(), terms);
      out.rowLog[i] = (rowTerms * coefficients.bottomRows(terms)).transpose().array();
    }
  }
  return out;
}

}  // namespace slicecap::prior
