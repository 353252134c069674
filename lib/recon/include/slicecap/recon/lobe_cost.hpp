// The Ceres cost of the elevation lobe: one residual per sample, analytic derivatives.
#pragma once

#include <ceres/cost_function.h>

#include <span>
#include <vector>

#include "slicecap/recon/lafortune_fit.hpp"

namespace slicecap::recon {

/// \brief The least-squares cost of the lobe k cos^n(theta), one residual a sample:
/// r_i = (exp((1 - t_i) a + t_i b) - y_i) / m_i, with t_i = (L_i - L_lo) / (L_hi - L_lo),
/// L = log cos theta, and m_i the mean of the samples at sample i's elevation; one parameter block
/// {a, b}: the model's log values at the lowest and highest sample elevation
/// (n = (b - a) / (L_hi - L_lo), log k = a - n L_lo).
///
/// Why: measured materials' elevation means differ by orders of magnitude (chrome: 4e-4 against
/// 75). In (log k, n) with plain residuals the dark group's pull is ~1e-9 of the cost, and
/// Levenberg-Marquardt stopped with n off by 1e-3 (TinySolver damps every column by at least
/// 1e-6). In (a, b) the Jacobian is diagonal for two elevations, and the group weights 1 / m give
/// both columns the same scale, so each mean is met in a few Gauss-Newton steps. With samples at
/// two elevations (Method B's lines) the optimum is unchanged: the curve through both group means.
///
/// One cost function holds every sample so that Ceres' TinySolver can minimise it through
/// TinySolverCostFunctionAdapter; the general Problem/Solver path cost 5-10x more per fit here,
/// which matters once per pixel in texture mode. Values are clamped to `minimumValue` first, as
/// docs/method.md §4.2 asks before logarithms.
class LobeCost final : public ceres::CostFunction {
 public:
  /// \brief Needs samples at two or more distinct elevations (ReconArgumentError otherwise).
  LobeCost(std::span<const ElevationSample> samples, double minimumValue);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// \brief The lobe of a parameter block {a, b}.
  ElevationLobe lobe(const double* parameters) const;
  /// \brief L_lo and L_hi: the start {a, b} = n0 (L_lo, L_hi) is the lobe k = 1, n = n0.
  double lowLogCos() const { return logCosLow_; }
  double highLogCos() const { return logCosLow_ + logCosSpan_; }

 private:
  double logCosLow_;   ///< L at the lowest sample elevation (largest cosine)
  double logCosSpan_;  ///< L_hi - L_lo (negative: cosines fall with elevation)
  // Samples grouped by elevation: the model is evaluated once a group (Method B has two).
  struct Group {
    double position;  ///< t of the group's elevation
    double weight;    ///< 1 / (mean of its samples)
  };
  std::vector<Group> groups_;
  std::vector<int> groupOf_;  ///< sample index -> group index
  std::vector<double> values_;
};

}  // namespace slicecap::recon
