// The prior fit: ridge regression of the basis (and half-vector terms) to log-mapped samples,
// model selection by generalised cross-validation, then the measured residuals kept.
#include "slicecap/prior/prior_reconstruction.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>

#include "half_vector_terms.hpp"
#include "isotropic_taps.hpp"
#include "residual_field.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/grid_interpolation.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/method_b.hpp"

namespace slicecap::prior {
namespace {

constexpr int kEntries = kFeatureCount;

struct SampleRow {
  std::vector<TableTap> taps;  ///< isotropicTableTaps: where the basis and mean are read
  std::vector<int> slots;      ///< per tap, its entry's row in TappedEntries
  HalfVectorTerms terms;       ///< the half-vector terms at the sample's own directions
  Rgb weighted;                ///< value times cos(theta_i) cos(theta_v), clipped at 0
  const SliceId* slice;
  double parameterDeg;
};

// One ridge fit of the design to the three channels' targets.
struct RidgeFit {
  Eigen::MatrixXd coefficients;  // columns x 3
  double score = std::numeric_limits<double>::infinity();
};

// The products of the full design that every nested fit (its first `columns` columns) reuses.
struct NormalEquations {
  Eigen::MatrixXd normal;         // D^T D
  Eigen::MatrixXd designTargets;  // D^T Y
  double targetSquares = 0.0;     // |Y|^2
  double rows = 0.0;
};

RidgeFit ridgeFit(const NormalEquations& equations, int columns, const Eigen::VectorXd& penalty) {
  const auto normal = equations.normal.topLeftCorner(columns, columns);
  const auto designTargets = equations.designTargets.topRows(columns);
  Eigen::MatrixXd system = normal;
  system.diagonal() += penalty.head(columns);
  const Eigen::LLT<Eigen::MatrixXd> llt(system);
  RidgeFit fit;
  fit.coefficients = llt.solve(designTargets);
  // |D c - Y|^2 = |Y|^2 - 2 c^T D^T Y + c^T D^T D c, summed over the channels.
  const double rss =
      std::max(0.0, equations.targetSquares -
                        2.0 * (fit.coefficients.array() * designTargets.array()).sum() +
                        (fit.coefficients.array() * (normal * fit.coefficients).array()).sum());
  // Effective parameters trace(S^-1 N) with S = N + P: columns - sum_j p_j (S^-1)_jj, and
  // (S^-1)_jj = |L^-1 e_j|^2 -- one triangular inverse instead of two solves with N as right side.
  const Eigen::MatrixXd inverseFactor =
      llt.matrixL().solve(Eigen::MatrixXd::Identity(columns, columns));
  double effective = columns;
  for (int j = 0; j < columns; ++j)
    effective -= penalty[j] * inverseFactor.col(j).squaredNorm();
  const double n = equations.rows;
  if (n > effective + 1e-9) fit.score = n * rss / 3.0 / ((n - effective) * (n - effective));
  return fit;
}

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The distinct table entries the samples' taps read, and the design's columns at each (the basis
// components, then the half-vector terms), gathered once. Off the grid (every jittered sample,
// every texel of a BTF) a sample reads up to 16 entries and its neighbours along the slice read
// most of the same ones; and the basis is stored component by component, so gathering one entry's
// features touches 16 cache lines. Everything computed per entry (the features, the fitted log
// values and their exponentials) is computed once per entry here, then blended per tap exactly as
// before.
struct TappedEntries {
  std::vector<int> entries;  // slot -> table entry (light * 81 + view)
  RowMajorMatrix features;   // slot x components
};

// `basisByEntry`: the basis entry by entry (PriorReconstructor), or null to read it from the model.
TappedEntries gatherTappedEntries(std::vector<SampleRow>& rows, const PriorModel& model,
                                  const float* basisByEntry) {
  TappedEntries out;
  std::vector<int> slotOf(kEntries, -1);
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

// The log values of the fitted model at each sample's taps (basis and mean, per slot) and, per
// row, its half-vector part at the sample's own directions: the model at a sample is
// sum_t w_t exp(slotLog_t + rowLog) (see refineOnLinearTaps).
struct SampleModel {
  std::vector<Eigen::Array3d> slotLog;  // per slot: mean + basis c
  std::vector<Eigen::Array3d> rowLog;   // per row: half-vector terms d
};

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

// One Gauss-Newton step from the fit above to the fit of the true measurement operator. The fit
// above models a sample as the taps' blend of the LOG table, but a sample is the taps' blend of
// the table's VALUES: log(sum_t w_t exp(L_t)). Off the grid (every jittered sample, every slice
// sample between two azimuths of a ring) the two differ most where L varies most, at highlights.
// Linearised at the current coefficients, a sample's row is the basis blended with the weights
// w_t exp(L_t) / sum (one set of weights for the three channels, from their mean log, so one
// system serves all three), then its own half-vector terms, which are the same for every tap.
// Model selection stays with the first fit; one step removes nearly all of the mismatch (a
// second changed the held-out mean dE by < 0.002).
Eigen::MatrixXd refineOnLinearTaps(const std::vector<SampleRow>& rows, const TappedEntries& tapped,
                                   const PriorModel& model, const Rgb& floor,
                                   const Eigen::VectorXd& penalty,
                                   const Eigen::MatrixXd& coefficients) {
  const int n = static_cast<int>(rows.size());
  const int columns = static_cast<int>(coefficients.rows());
  const int k = static_cast<int>(tapped.features.cols());
  const int terms = columns - k;
  const SampleModel fitted = sampleModel(rows, tapped, model, coefficients);
  const std::size_t slots = tapped.entries.size();
  std::vector<Eigen::Array3d> entryValues(slots);
  std::vector<double> entryShares(slots);
  for (std::size_t s = 0; s < slots; ++s) {
    entryShares[s] = std::exp(fitted.slotLog[s].mean());
    entryValues[s] = fitted.slotLog[s].exp();
  }
  Eigen::MatrixXd jacobian(n, columns);
  Eigen::MatrixXd linearTargets(n, 3);
  Eigen::RowVectorXd basisRow(k);
  for (int i = 0; i < n; ++i) {
    double shareSum = 0.0;
    Eigen::Array3d predicted = Eigen::Array3d::Zero();
    basisRow.setZero();
    const SampleRow& row = rows[std::size_t(i)];
    for (std::size_t t = 0; t < row.taps.size(); ++t) {
      const std::size_t s = std::size_t(row.slots[t]);
      const double share = row.taps[t].weight * entryShares[s];
      basisRow += share * tapped.features.row(Eigen::Index(s));
      shareSum += share;
      predicted += row.taps[t].weight * entryValues[s];
    }
    predicted *= fitted.rowLog[std::size_t(i)].exp();
    jacobian.row(i).head(k) = basisRow / shareSum;
    for (int j = 0; j < terms; ++j)
      jacobian(i, k + j) = row.terms[std::size_t(j)];
    for (int c = 0; c < 3; ++c)
      linearTargets(i, c) = std::log(rows[i].weighted[c] + floor[c]) - std::log(predicted[c]) +
                            jacobian.row(i).dot(coefficients.col(c));
  }
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(columns, columns);
  system.selfadjointView<Eigen::Lower>().rankUpdate(jacobian.transpose());
  system.diagonal() += penalty;
  return system.selfadjointView<Eigen::Lower>().llt().solve(jacobian.transpose() * linearTargets);
}

// The natural log of the largest cos-weighted sample over the median one (luminance, the mean of
// the channels): how much directional structure the samples show. Infinite when the median is 0.
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

// The reconstruction; `basisByEntry` as for gatherTappedEntries.
Abrdf reconstruct(const SliceSet& slices, const PriorModel& model, const PriorParams& params,
                  PriorReport* report, const float* basisByEntry);

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
  return true;
}

Abrdf reconstructWithPrior(const SliceSet& slices, const PriorModel& model,
                           const PriorParams& params, PriorReport* report) {
  std::string error;
  if (!params.isValid(&error)) throw std::invalid_argument("prior reconstruction: " + error);
  return reconstruct(slices, model, params, report, nullptr);
}

PriorReconstructor::PriorReconstructor(const PriorModel& model, const PriorParams& params)
    : model_(&model), params_(params) {
  std::string error;
  if (!params.isValid(&error)) throw std::invalid_argument("prior reconstruction: " + error);
  const int k = model.components();
  if (model.basis.size() != std::size_t(k) * kEntries)
    throw std::invalid_argument("prior reconstruction: the basis must hold components x 6561");
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

namespace {

Abrdf reconstruct(const SliceSet& slices, const PriorModel& model, const PriorParams& params,
                  PriorReport* report, const float* basisByEntry) {
  std::vector<SampleRow> rows;
  rows.reserve(slices.sampleCount());
  for (const Slice& slice : slices.slices()) {
    for (const SliceSample& s : slice.samples) {
      SampleRow row{{}, {}, {}, {}, &slice.id, sliceParameterDeg(slice.id.kind, s)};
      try {
        // See PriorParams::readAtMeasuredAngles.
        if (params.readAtMeasuredAngles) {
          row.taps = isotropicTableTaps(s.light, s.view);
          row.terms = halfVectorTerms(toUnitVector(s.light), toUnitVector(s.view));
        } else {
          row.taps = tableTaps(s.light, s.view);
          for (const TableTap& tap : row.taps) {
            const HalfVectorTerms& entryTerms =
                gridHalfVectorTerms()[std::size_t(tap.light * 81 + tap.view)];
            for (int j = 0; j < kHalfVectorTermCount; ++j)
              row.terms[std::size_t(j)] += tap.weight * entryTerms[std::size_t(j)];
          }
        }
      } catch (const std::invalid_argument& e) {
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
        if (!std::isfinite(s.value[c]))
          throw recon::ReconstructionError("slice " + toString(slice.id) + ": non-finite sample");
        row.weighted[c] = std::max(0.0, s.value[c]) * cc;
      }
      rows.push_back(std::move(row));
    }
  }
  if (rows.empty()) throw recon::ReconstructionError("the prior needs at least one sample");

  // The floor of the log map, per channel, relative to the largest sample (as in training).
  Rgb floor;
  for (const SampleRow& r : rows) {
    for (std::size_t c = 0; c < 3; ++c)
      floor[c] = std::max(floor[c], r.weighted[c]);
  }
  for (std::size_t c = 0; c < 3; ++c)
    floor[c] = std::max(floor[c] * model.floorFraction, std::numeric_limits<double>::min());

  const int n = static_cast<int>(rows.size());
  const int k = model.components();
  const auto& gridTerms = gridHalfVectorTerms();
  const TappedEntries tapped = gatherTappedEntries(rows, model, basisByEntry);
  Eigen::MatrixXd design(n, k + kHalfVectorTermCount);
  Eigen::MatrixXd targets(n, 3);
  Eigen::RowVectorXd designRow(k);
  for (int i = 0; i < n; ++i) {
    double meanAtSample = 0.0;
    designRow.setZero();
    const SampleRow& row = rows[std::size_t(i)];
    for (std::size_t t = 0; t < row.taps.size(); ++t) {
      const TableTap& tap = row.taps[t];
      meanAtSample += tap.weight * model.mean[std::size_t(tap.light * 81 + tap.view)];
      designRow += tap.weight * tapped.features.row(row.slots[t]);
    }
    design.row(i).head(k) = designRow;
    for (int j = 0; j < kHalfVectorTermCount; ++j)
      design(i, k + j) = row.terms[std::size_t(j)];
    for (int c = 0; c < 3; ++c)
      targets(i, c) = std::log(rows[i].weighted[c] + floor[c]) - meanAtSample;
  }
  // Two or fewer measured elevation pairs (e.g. the two diagonal sweeps 30/30 and 75/75): the
  // lighter ridge of PriorParams::fewPairsRidge.
  std::vector<ElevationPair> pairs;
  for (const Slice& s : slices.slices())
    if (std::find(pairs.begin(), pairs.end(), s.id.elevations) == pairs.end())
      pairs.push_back(s.id.elevations);
  const double ridge = pairs.size() <= 2 ? params.fewPairsRidge : params.ridge;
  Eigen::VectorXd penalty(k + kHalfVectorTermCount);
  for (int j = 0; j < k; ++j)
    penalty[j] = ridge * model.residualVariance / model.variance[j];
  penalty.tail(kHalfVectorTermCount).setConstant(params.anisotropyRidge);

  // The isotropic fit: the basis alone, or with the isotropic hats when they lower the GCV score.
  const int isotropicColumns = k + kIsotropicTermCount;
  NormalEquations equations;
  // D^T D is symmetric: one triangle by a rank update (half the work of the full product).
  equations.normal = Eigen::MatrixXd::Zero(design.cols(), design.cols());
  equations.normal.selfadjointView<Eigen::Lower>().rankUpdate(design.transpose());
  equations.normal.triangularView<Eigen::StrictlyUpper>() = equations.normal.transpose();
  equations.designTargets.noalias() = design.transpose() * targets;
  equations.targetSquares = targets.squaredNorm();
  equations.rows = double(n);
  const RidgeFit basisOnly = ridgeFit(equations, k, penalty);
  const RidgeFit withHats = ridgeFit(equations, isotropicColumns, penalty);
  const RidgeFit& isotropic = withHats.score < basisOnly.score ? withHats : basisOnly;
  RidgeFit anisotropic;
  if (!params.isotropicOnly) anisotropic = ridgeFit(equations, k + kHalfVectorTermCount, penalty);
  const bool useAnisotropy =
      !params.isotropicOnly && anisotropic.score < params.anisotropyScoreRatio * isotropic.score;

  // The fitted log table L = mean + basis c + half-vector terms d, [entry][channel].
  const RidgeFit& chosen = useAnisotropy ? anisotropic : isotropic;
  const int columnsUsed = static_cast<int>(chosen.coefficients.rows());
  const int termsUsed = columnsUsed - k;
  const Eigen::Map<const Eigen::MatrixXf> basis(model.basis.data(), kEntries, k);
  using TermMatrix = Eigen::Matrix<float, Eigen::Dynamic, kHalfVectorTermCount, Eigen::RowMajor>;
  static const TermMatrix terms =
      Eigen::Map<
          const Eigen::Matrix<double, Eigen::Dynamic, kHalfVectorTermCount, Eigen::RowMajor>>(
          gridTerms[0].data(), kEntries, kHalfVectorTermCount)
          .cast<float>();
  const Eigen::MatrixXd refined = refineOnLinearTaps(
      rows, tapped, model, floor, penalty.head(columnsUsed), chosen.coefficients);
  const Eigen::MatrixXf coefficients = refined.topRows(k).cast<float>();
  const Eigen::MatrixXf termCoefficients = refined.bottomRows(termsUsed).cast<float>();
  Eigen::MatrixXf logTable = basis * coefficients;
  logTable.colwise() += Eigen::Map<const Eigen::VectorXf>(model.mean.data(), kEntries);
  // One matrix-vector product per channel over a float copy of the grid's terms (a general
  // matrix product would repack the 6561 x 30 terms on every call), in blocks of rows so that
  // the three channels read a block while it is in the cache (the terms are 787 kB). Each row is
  // its own dot product, and blocks of a multiple of 8 rows keep every row on the kernel path it
  // takes in one product over all rows: the same sums to the bit.
  if (termsUsed > 0) {
    constexpr int kBlockRows = 512;
    for (int first = 0; first < kEntries; first += kBlockRows) {
      const int blockRows = std::min(kBlockRows, kEntries - first);
      for (int c = 0; c < 3; ++c)
        logTable.col(c).segment(first, blockRows).noalias() +=
            terms.block(first, 0, blockRows, termsUsed) * termCoefficients.col(c);
    }
  }

  // The samples' residuals against the fitted model at their own angles (linear taps, their
  // own half-vector terms). The residual field puts them at the slice's nominal elevation pair:
  // a ratio to the model moves with the model, so a sample taken a few degrees off its pair is
  // corrected to the pair by the fitted model's own change over those degrees.
  const SampleModel fitted = sampleModel(rows, tapped, model, refined);
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

  // Where the samples show little directional structure, blend with Method B (see PriorParams).
  const double dynamicRange = sampleDynamicRangeLog(rows);
  const double wanted = params.blendWithMethodB ? priorWeightFor(dynamicRange, params) : 1.0;
  const std::optional<Abrdf> methodB =
      wanted < 1.0 ? methodBWhereItRuns(slices) : std::optional<Abrdf>{};
  const float priorWeight = methodB ? static_cast<float>(wanted) : 1.0f;

  // Back from the log domain in passes over the table (log values and the blend, exp, then the
  // floor and the cosines): the exp calls then run back to back instead of waiting on a division
  // each, which made one fused loop the slowest part of the fit.
  static const std::vector<float> entryCosines = [] {
    std::vector<float> cc(kEntries);
    for (int l = 0; l < 81; ++l)
      for (int v = 0; v < 81; ++v)
        cc[l * 81 + v] = static_cast<float>(bonn::cosines()[l] * bonn::cosines()[v]);
    return cc;
  }();
  std::array<float, 3> floors{};
  for (int c = 0; c < 3; ++c)
    floors[c] = static_cast<float>(floor[c]);
  Abrdf table;
  const std::span<float> values = table.values();  // [entry][channel]
  for (int e = 0; e < kEntries; ++e) {
    for (int c = 0; c < 3; ++c)
      values[e * 3 + c] = logTable(e, c);
  }
  if (priorWeight < 1.0f) {
    // In the prior's own log domain, log(f cos cos + floor): both tables keep the samples, so the
    // blend keeps them too.
    const std::span<const float> methodBValues = methodB->values();
    for (int e = 0; e < kEntries; ++e) {
      for (int c = 0; c < 3; ++c) {
        const float logB =
            std::log(std::max(methodBValues[e * 3 + c], 0.0f) * entryCosines[e] + floors[c]);
        values[e * 3 + c] = priorWeight * values[e * 3 + c] + (1.0f - priorWeight) * logB;
      }
    }
  }
  // In float: the table is float, and expf is several times cheaper than exp over 19683 values.
  for (float& v : values)
    v = std::exp(v);
  for (int e = 0; e < kEntries; ++e) {
    for (int c = 0; c < 3; ++c)
      values[e * 3 + c] = std::max((values[e * 3 + c] - floors[c]) / entryCosines[e], 0.0f);
  }
  if (report) {
    report->samples = rows.size();
    report->measuredPairs = pairs;
    report->anisotropyTermsUsed = useAnisotropy;
    report->isotropicScore = isotropic.score;
    report->anisotropicScore = params.isotropicOnly ? 0.0 : anisotropic.score;
    report->fitRmsLog = std::sqrt(squares / (3.0 * n));
    report->dynamicRangeLog = dynamicRange;
    report->priorWeight = priorWeight;
    report->methodBBlended = priorWeight < 1.0f;
  }
  return table;
}

}  // namespace

}  // namespace slicecap::prior
