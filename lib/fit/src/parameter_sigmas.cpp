// cov = s^2 (J^T J)^+ with s^2 = 2 cost / (N - p); a direction J^T J does not see (the tangent of
// a round lobe, a colour of a term that is absent) leaves the parameters along it undetermined.
#include "parameter_sigmas.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "slicecap/core/angles.hpp"

namespace slicecap::fit::detail {
namespace {

// Eigenvalues below this fraction of the largest count as unseen: double precision leaves about
// 1e-16 of the largest in the smallest, and (J^T J)'s condition is the square of J's.
constexpr double kNullRelativeEigenvalue = 1e-10;
// A parameter with more than this share of its unit vector in the unseen directions is undetermined.
constexpr double kUndeterminedShare = 0.01;

}  // namespace

ParameterSigmas parameterSigmas(const FitData& data, const SolveOutcome& solution,
                                const FittedMaterial& material) {
  const Eigen::MatrixXd jacobian = jacobianAt(data, solution.parameters);
  const Eigen::Index n = jacobian.cols();
  const Eigen::MatrixXd normal = jacobian.transpose() * jacobian;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normal);
  const double largest = eigen.eigenvalues().maxCoeff();
  const double degreesOfFreedom = std::max(1.0, double(data.residualCount()) - double(n));
  const double variance = 2.0 * solution.cost / degreesOfFreedom;

  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd unseenShare = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double lambda = eigen.eigenvalues()(k);
    const Eigen::VectorXd v = eigen.eigenvectors().col(k);
    if (!(lambda > kNullRelativeEigenvalue * largest)) {
      unseenShare += v.cwiseAbs2();
    } else {
      covariance += v * v.transpose() * (variance / lambda);
    }
  }
  const auto sigma = [&](Eigen::Index i, double unitScale) -> std::optional<double> {
    if (unseenShare(i) > kUndeterminedShare) return std::nullopt;
    return std::sqrt(std::max(0.0, covariance(i, i))) * unitScale;
  };

  ParameterSigmas s;
  for (Eigen::Index c = 0; c < 3; ++c) {
    s.diffuseAlbedo[static_cast<std::size_t>(c)] = sigma(c, 1.0);
    s.specularF0[static_cast<std::size_t>(c)] = sigma(3 + c, 1.0);
  }
  // d alpha = alpha d(log alpha). canonical() swapped the alphas when the raw tangent alpha was
  // the smaller one.
  const bool swapped = std::exp(solution.parameters.ggx[6]) < std::exp(solution.parameters.ggx[7]);
  s.alphaTangent = sigma(swapped ? 7 : 6, material.alphaTangent);
  s.alphaBitangent = sigma(swapped ? 6 : 7, material.alphaBitangent);
  s.tangentDeg = sigma(8, radToDeg(1.0));
  s.specularF90 = sigma(9, 1.0);
  if (solution.parameters.withSheen) {
    for (Eigen::Index c = 0; c < 3; ++c)
      s.sheenColour[static_cast<std::size_t>(c)] = sigma(10 + c, 1.0);
    s.sheenRoughness = sigma(13, material.sheenRoughness);
  }
  if (solution.parameters.withCoat) {
    const Eigen::Index coat = solution.parameters.coatOffset();
    s.coatWeight = sigma(coat, 1.0);
    s.coatAlpha = sigma(coat + 1, material.coatAlpha);
  }
  return s;
}

}  // namespace slicecap::fit::detail
