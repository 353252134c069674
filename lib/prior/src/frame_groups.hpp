// The cells of one frame fitted as a group whose errors are correlated: generalised least squares
// with a random frame effect, applied as a whitening of the design's rows (docs/method.md §9.4,
// "The prior on every cell").
#pragma once

#include <Eigen/Core>
#include <vector>

#include "prior_samples.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::prior {

/// \brief Per row, how it is whitened: row_i <- scale_i (row_i - gamma_g sum_{j in g} share_j
/// row_j) within its frame group g; rows outside any group are left as they are.
///
/// The error model, log domain: a cell i of frame g has e_i = a_g + u_i, a_g the frame's common
/// error (variance s^2: its irradiance fit, exposure, pose), u_i its own (variance t^2 + v_i: t^2
/// what a lone sample's error is besides the frame's, v_i the cell's noise). In units where a
/// lone noise-free sample outside any frame has weight 1 (as every sample of a fit without cells),
/// with rho = s^2 / t^2 and w_i = t^2 / (t^2 + v_i), the inverse covariance of the group is
/// (1 + rho) (W - rho / (1 + rho S) w w^T), S = sum w_i (Sherman-Morrison); it is T^T T for
/// T = sqrt(1 + rho) W^(1/2) (I - gamma 1 (w / S)^T) with gamma = 1 - 1 / sqrt(1 + rho S). So
/// the frame's mean level counts (1 + rho) S / (1 + rho S) <= (1 + rho) / rho lone samples however
/// many cells it has, and each cell's difference from it counts (1 + rho) w_i.
struct FrameWhitening {
  std::vector<double> scale;  ///< per row: sqrt((1 + rho) w_i); 1 outside a group
  std::vector<double> share;  ///< per row: w_i / S of its group; 0 outside a group
  std::vector<double> gamma;  ///< per group
  std::vector<int> group;     ///< per row: its group, -1 for none
  bool any() const { return !gamma.empty(); }
};

/// \brief The whitening of `rows` (their frame groups and weighted variances), `floor` the log
/// map's floor (a cell's log-domain noise is its variance over (value + floor)^2, the channels'
/// mean). `ownLogSigma` t and `commonLogSigma` s as above; t must be positive.
/// With `asOneSample`, each group instead weighs as one lone sample, shared by w_i / S (scale
/// sqrt(w_i / S), gamma 0).
FrameWhitening frameWhitening(const std::vector<SampleRow>& rows, const Rgb& floor,
                              double ownLogSigma, double commonLogSigma, bool asOneSample);

/// \brief Applies `whitening` to the rows of `m` (one per sample row), in place.
void whiten(const FrameWhitening& whitening, Eigen::Ref<Eigen::MatrixXd> m);

}  // namespace slicecap::prior
