// The prior reconstruction: the samples' fit (prior_fit), the fitted log table, the measured
// residuals kept, a blend with Method B where the samples show little structure.
#include "slicecap/prior/prior_reconstruction.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>

#include "prior_fit.hpp"
#include "prior_samples.hpp"
#include "residual_field.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/prior/prior_model.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/method_b.hpp"

namespace slicecap::prior {
namespace {

constexpr int kEntries = kFeatureCount;

// The fitted log table L = mean + basis c + half-vector terms d, [entry][channel].
Eigen::MatrixXf fittedLogTable(const PriorModel& model, const PriorFit& fit) {
  const int k = model.components();
  const Eigen::Map<const Eigen::MatrixXf> basis(model.basis.data(), kEntries, k);
  using TermMatrix = Eigen::Matrix<float, Eigen::Dynamic, kHalfVectorTermCount, Eigen::RowMajor>;
  static const TermMatrix terms =
      Eigen::Map<
          const Eigen::Matrix<double, Eigen::Dynamic, kHalfVectorTermCount, Eigen::RowMajor>>(
          gridHalfVectorTerms()[0].data(), kEntries, kHalfVectorTermCount)
          .cast<float>();
  const Eigen::MatrixXf coefficients = fit.coefficients.topRows(k).cast<float>();
  const Eigen::MatrixXf termCoefficients = fit.coefficients.bottomRows(fit.termsUsed).cast<float>();
  Eigen::MatrixXf logTable = basis * coefficients;
  logTable.colwise() += Eigen::Map<const Eigen::VectorXf>(model.mean.data(), kEntries);
  // One matrix-vector product per channel over a float copy of the grid's terms (a general
  // matrix product would repack the 6561 x 30 terms on every call), in blocks of rows so that
  // the three channels read a block while it is in the cache (the terms are 787 kB). Each row is
  // its own dot product, and blocks of a multiple of 8 rows keep every row on the kernel path it
  // takes in one product over all rows: the same sums to the bit.
  if (fit.termsUsed > 0) {
    constexpr int kBlockRows = 512;
    for (int first = 0; first < kEntries; first += kBlockRows) {
      const int blockRows = std::min(kBlockRows, kEntries - first);
      for (int c = 0; c < 3; ++c)
        logTable.col(c).segment(first, blockRows).noalias() +=
            terms.block(first, 0, blockRows, fit.termsUsed) * termCoefficients.col(c);
    }
  }
  return logTable;
}

// The samples' residuals against the fitted model at their own angles (linear taps, their own
// half-vector terms), added to `logTable` as a field. The residual field puts them at the slice's
// nominal elevation pair: a ratio to the model moves with the model, so a sample taken a few
// degrees off its pair is corrected to the pair by the fitted model's own change over those
// degrees. Returns the sum of the squared residuals over the channels.
double keepResiduals(const std::vector<SampleRow>& rows, const TappedEntries& tapped,
                     const PriorModel& model, const PriorFit& fit, const Rgb& floor,
                     Eigen::MatrixXf& logTable) {
  const SampleModel fitted = sampleModel(rows, tapped, model, fit.coefficients);
  SliceResiduals residuals;
  double squares = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SampleRow& r = rows[i];
    Rgb predicted;
    const Eigen::Array3d rowFactor = fitted.rowLog[i].exp();
    for (std::size_t t = 0; t < r.taps.size(); ++t) {
      const Eigen::Array3d value = fitted.slotLog[std::size_t(r.slots[t])].exp() * rowFactor;
      for (int c = 0; c < 3; ++c)
        predicted[c] += r.taps[t].weight * (value[c] - floor[c]);
    }
    Rgb residual;
    for (std::size_t c = 0; c < 3; ++c) {
      residual[c] =
          std::log(r.weighted[c] + floor[c]) - std::log(std::max(predicted[c], 0.0) + floor[c]);
      squares += residual[c] * residual[c];
    }
    residuals[*r.slice].push_back({r.parameterDeg, residual});
  }
  addResidualField(residuals, logTable);
  return squares;
}

double priorWeightFor(double dynamicRangeLog, const PriorParams& params) {
  const double t =
      (dynamicRangeLog - params.blendFromLog) / (params.blendToLog - params.blendFromLog);
  return std::clamp(t, 0.0, 1.0);
}

// Method B on these slices: all eight, or the four diagonal ones (its isotropic form); nothing
// when neither set is complete (e.g. two diagonal sweeps), and the prior then stands alone.
std::optional<Abrdf> methodBWhereItRuns(const SliceSet& slices) {
  auto complete = [&](bool diagonalOnly) {
    for (const ElevationPair& pair : kMeasuredPairs) {
      if (!slices.find({SliceKind::Diagonal, pair})) return false;
      if (!diagonalOnly && !slices.find({SliceKind::Axial, pair})) return false;
    }
    return true;
  };
  recon::MethodBParams params;
  if (!complete(false)) {
    if (!complete(true)) return std::nullopt;
    params.isotropic = true;
  }
  try {
    return recon::reconstructMethodB(slices, params);
  } catch (const recon::ReconstructionError&) {
    return std::nullopt;  // e.g. a slice too sparse for B; the prior reads any samples
  }
}

const std::vector<float>& entryCosines() {
  static const std::vector<float> cc = [] {
    std::vector<float> out(kEntries);
    for (int l = 0; l < 81; ++l)
      for (int v = 0; v < 81; ++v)
        out[l * 81 + v] = static_cast<float>(bonn::cosines()[l] * bonn::cosines()[v]);
    return out;
  }();
  return cc;
}

// The table from the log one: blended with Method B's (when given, in the prior's own log domain,
// log(f cos cos + floor): both tables keep the samples, so the blend keeps them too), then back
// from the log domain in passes over the table (the exp calls then run back to back instead of
// waiting on a division each, which made one fused loop the slowest part of the fit).
Abrdf tableFromLog(const Eigen::MatrixXf& logTable, const Rgb& floor, const Abrdf* methodB,
                   float priorWeight) {
  std::array<float, 3> floors{};
  for (int c = 0; c < 3; ++c)
    floors[c] = static_cast<float>(floor[c]);
  const std::vector<float>& cosines = entryCosines();
  Abrdf table;
  const std::span<float> values = table.values();  // [entry][channel]
  for (int e = 0; e < kEntries; ++e) {
    for (int c = 0; c < 3; ++c)
      values[e * 3 + c] = logTable(e, c);
  }
  if (methodB) {
    const std::span<const float> methodBValues = methodB->values();
    for (int e = 0; e < kEntries; ++e) {
      for (int c = 0; c < 3; ++c) {
        const float logB =
            std::log(std::max(methodBValues[e * 3 + c], 0.0f) * cosines[e] + floors[c]);
        values[e * 3 + c] = priorWeight * values[e * 3 + c] + (1.0f - priorWeight) * logB;
      }
    }
  }
  // In float: the table is float, and expf is several times cheaper than exp over 19683 values.
  for (float& v : values)
    v = std::exp(v);
  for (int e = 0; e < kEntries; ++e) {
    for (int c = 0; c < 3; ++c)
      values[e * 3 + c] = std::max((values[e * 3 + c] - floors[c]) / cosines[e], 0.0f);
  }
  return table;
}

// The reconstruction; `basisByEntry` as for gatherTappedEntries.
Abrdf reconstruct(const SliceSet& slices, const PriorModel& model, const PriorParams& params,
                  PriorReport* report, const float* basisByEntry) {
  // The slices' samples give the residuals kept and the dynamic range; the fit reads every cell
  // instead where asked and the slices have them (PriorParams::fitEveryCell).
  std::vector<SampleRow> rows = gatherSampleRows(slices, params.readAtMeasuredAngles);
  std::vector<SampleRow> cellRows;
  if (params.fitEveryCell && slices.hasCellFrames())
    cellRows = gatherCellRows(slices, params.readAtMeasuredAngles);
  std::vector<SampleRow>& fitRows = cellRows.empty() ? rows : cellRows;
  const Rgb floor = logFloor(fitRows, model.floorFraction);
  const TappedEntries fitTapped = gatherTappedEntries(fitRows, model, basisByEntry);
  const PriorFit fit = fitPrior(slices, fitRows, fitTapped, model, params, floor);
  Eigen::MatrixXf logTable = fittedLogTable(model, fit);
  const TappedEntries tapped =
      cellRows.empty() ? fitTapped : gatherTappedEntries(rows, model, basisByEntry);
  const double squares = keepResiduals(rows, tapped, model, fit, floor, logTable);

  // Where the samples show little directional structure, blend with Method B (see PriorParams).
  const double dynamicRange = sampleDynamicRangeLog(rows);
  const double wanted = params.blendWithMethodB ? priorWeightFor(dynamicRange, params) : 1.0;
  const std::optional<Abrdf> methodB =
      wanted < 1.0 ? methodBWhereItRuns(slices) : std::optional<Abrdf>{};
  const float priorWeight = methodB ? static_cast<float>(wanted) : 1.0f;
  Abrdf table =
      tableFromLog(logTable, floor, priorWeight < 1.0f ? &*methodB : nullptr, priorWeight);
  if (report) {
    report->samples = fitRows.size();
    report->frameGroups = std::size_t(frameGroupCount(fitRows));
    report->measuredPairs = fit.measuredPairs;
    report->anisotropyTermsUsed = fit.anisotropyTermsUsed;
    report->isotropicScore = fit.isotropicScore;
    report->anisotropicScore = fit.anisotropicScore;
    report->fitRmsLog = std::sqrt(squares / (3.0 * double(rows.size())));
    report->dynamicRangeLog = dynamicRange;
    report->priorWeight = priorWeight;
    report->methodBBlended = priorWeight < 1.0f;
  }
  return table;
}

}  // namespace

bool PriorParams::isValid(std::string* error) const {
  auto bad = [&](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (!(ridge > 0.0) || !std::isfinite(ridge)) return bad("ridge must be positive");
  if (!(fewPairsRidge > 0.0) || !std::isfinite(fewPairsRidge))
    return bad("few-pairs ridge must be positive");
  if (!(anisotropyRidge > 0.0) || !std::isfinite(anisotropyRidge))
    return bad("anisotropy ridge must be positive");
  if (!(anisotropyScoreRatio >= 0.0 && anisotropyScoreRatio <= 1.0))
    return bad("anisotropy score ratio must lie in [0, 1]");
  if (!std::isfinite(blendFromLog) || !std::isfinite(blendToLog) || !(blendFromLog >= 0.0) ||
      !(blendToLog > blendFromLog))
    return bad("the blend range must satisfy 0 <= from < to");
  if (!(cellOwnLogSigma > 0.0) || !std::isfinite(cellOwnLogSigma))
    return bad("a cell's own log sigma must be positive");
  if (!(frameCommonLogSigma >= 0.0) || !std::isfinite(frameCommonLogSigma))
    return bad("a frame's common log sigma must be 0 or more");
  return true;
}

Abrdf reconstructWithPrior(const SliceSet& slices, const PriorModel& model,
                           const PriorParams& params, PriorReport* report) {
  std::string error;
  if (!params.isValid(&error)) throw PriorError("prior reconstruction: " + error);
  return reconstruct(slices, model, params, report, nullptr);
}

PriorReconstructor::PriorReconstructor(const PriorModel& model, const PriorParams& params)
    : model_(&model), params_(params) {
  std::string error;
  if (!params.isValid(&error)) throw PriorError("prior reconstruction: " + error);
  const int k = model.components();
  if (model.basis.size() != std::size_t(k) * kEntries)
    throw PriorError("prior reconstruction: the basis must hold components x 6561");
  basisByEntry_.resize(model.basis.size());
  for (int j = 0; j < k; ++j) {
    const float* component = model.component(j);
    for (int e = 0; e < kEntries; ++e)
      basisByEntry_[std::size_t(e) * k + j] = component[e];
  }
}

Abrdf PriorReconstructor::reconstruct(const SliceSet& slices, PriorReport* report) const {
  return prior::reconstruct(slices, *model_, params_, report, basisByEntry_.data());
}

}  // namespace slicecap::prior
