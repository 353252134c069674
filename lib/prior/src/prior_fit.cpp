// The prior's coefficients: ridge regression of the basis (and half-vector terms) to log-mapped
// samples, model selection by generalised cross-validation, one Gauss-Newton step to linear taps.
#include "prior_fit.hpp"

#include "frame_groups.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace slicecap::prior {
namespace {

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
                                   const Eigen::MatrixXd& coefficients,
                                   const FrameWhitening& whitening) {
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
  whiten(whitening, jacobian);
  whiten(whitening, linearTargets);
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(columns, columns);
  system.selfadjointView<Eigen::Lower>().rankUpdate(jacobian.transpose());
  system.diagonal() += penalty;
  return system.selfadjointView<Eigen::Lower>().llt().solve(jacobian.transpose() * linearTargets);
}

// The design (basis at each sample's taps, then its half-vector terms) and the log targets.
void buildDesign(const std::vector<SampleRow>& rows, const TappedEntries& tapped,
                 const PriorModel& model, const Rgb& floor, Eigen::MatrixXd& design,
                 Eigen::MatrixXd& targets) {
  const int n = static_cast<int>(rows.size());
  const int k = model.components();
  design.resize(n, k + kHalfVectorTermCount);
  targets.resize(n, 3);
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
}

NormalEquations normalEquations(const Eigen::MatrixXd& design, const Eigen::MatrixXd& targets) {
  NormalEquations equations;
  // D^T D is symmetric: one triangle by a rank update (half the work of the full product).
  equations.normal = Eigen::MatrixXd::Zero(design.cols(), design.cols());
  equations.normal.selfadjointView<Eigen::Lower>().rankUpdate(design.transpose());
  equations.normal.triangularView<Eigen::StrictlyUpper>() = equations.normal.transpose();
  equations.designTargets.noalias() = design.transpose() * targets;
  equations.targetSquares = targets.squaredNorm();
  equations.rows = double(design.rows());
  return equations;
}

}  // namespace

PriorFit fitPrior(const SliceSet& slices, const std::vector<SampleRow>& rows,
                  const TappedEntries& tapped, const PriorModel& model, const PriorParams& params,
                  const Rgb& floor) {
  const int k = model.components();
  Eigen::MatrixXd design;
  Eigen::MatrixXd targets;
  buildDesign(rows, tapped, model, floor, design, targets);
  // One frame's cells as one group with correlated errors (rows outside a group as they are).
  const FrameWhitening whitening =
      frameWhitening(rows, floor, params.cellOwnLogSigma, params.frameCommonLogSigma,
                     params.frameAsOneSample);
  whiten(whitening, design);
  whiten(whitening, targets);
  PriorFit out;
  // Two or fewer measured elevation pairs (e.g. the two diagonal sweeps 30/30 and 75/75): the
  // lighter ridge of PriorParams::fewPairsRidge.
  for (const Slice& s : slices.slices())
    if (std::find(out.measuredPairs.begin(), out.measuredPairs.end(), s.id.elevations) ==
        out.measuredPairs.end())
      out.measuredPairs.push_back(s.id.elevations);
  const double ridge = out.measuredPairs.size() <= 2 ? params.fewPairsRidge : params.ridge;
  Eigen::VectorXd penalty(k + kHalfVectorTermCount);
  for (int j = 0; j < k; ++j)
    penalty[j] = ridge * model.residualVariance / model.variance[j];
  penalty.tail(kHalfVectorTermCount).setConstant(params.anisotropyRidge);

  // The isotropic fit: the basis alone, or with the isotropic hats when they lower the GCV score.
  // Its generalised cross-validation counts every row, each cell too: counting a frame's cells
  // once (as the weights do) chose the isotropic fit on satin-blue-45's cells and did worse
  // (docs/results/2026-12-06-window-cells.md, "The prior on every cell").
  const NormalEquations equations = normalEquations(design, targets);
  const RidgeFit basisOnly = ridgeFit(equations, k, penalty);
  const RidgeFit withHats = ridgeFit(equations, k + kIsotropicTermCount, penalty);
  const RidgeFit& isotropic = withHats.score < basisOnly.score ? withHats : basisOnly;
  RidgeFit anisotropic;
  if (!params.isotropicOnly) anisotropic = ridgeFit(equations, k + kHalfVectorTermCount, penalty);
  out.anisotropyTermsUsed =
      !params.isotropicOnly && anisotropic.score < params.anisotropyScoreRatio * isotropic.score;
  out.isotropicScore = isotropic.score;
  out.anisotropicScore = params.isotropicOnly ? 0.0 : anisotropic.score;

  const RidgeFit& chosen = out.anisotropyTermsUsed ? anisotropic : isotropic;
  const int columnsUsed = static_cast<int>(chosen.coefficients.rows());
  out.termsUsed = columnsUsed - k;
  out.coefficients = refineOnLinearTaps(rows, tapped, model, floor, penalty.head(columnsUsed),
                                        chosen.coefficients, whitening);
  return out;
}

}  // namespace slicecap::prior
