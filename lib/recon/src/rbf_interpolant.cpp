// The factored RBF system and its evaluation rows.
#include "slicecap/recon/rbf_interpolant.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

double squaredDistance(const FeaturePoint& a, const FeaturePoint& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    sum += (a[k] - b[k]) * (a[k] - b[k]);
  return sum;
}

}  // namespace

bool RbfParams::isValid(std::string* error) const {
  if (shapeRad && !(std::isfinite(*shapeRad) && *shapeRad > 0.0)) {
    if (error) *error = "the RBF shape parameter r0 must be positive";
    return false;
  }
  if (!(std::isfinite(valueGamma) && valueGamma > 0.0)) {
    if (error) *error = "the RBF value gamma must be positive";
    return false;
  }
  if (!(std::isfinite(shapeScale) && shapeScale > 0.0)) {
    if (error) *error = "the RBF r0 scale must be positive";
    return false;
  }
  return true;
}

int polynomialTerms(RbfPolynomial polynomial) {
  return polynomial == RbfPolynomial::Linear ? 5 : 1;
}

double toInterpolatedValue(double value, double valueGamma) {
  const double v = std::max(0.0, value);
  return valueGamma == 1.0 ? v : std::pow(v, 1.0 / valueGamma);
}

double fromInterpolatedValue(double interpolated, double valueGamma) {
  const double v = std::max(0.0, interpolated);
  return valueGamma == 1.0 ? v : std::pow(v, valueGamma);
}

double medianNearestNeighbourDistance(std::span<const FeaturePoint> points) {
  if (points.size() < 2) return 0.0;
  std::vector<double> nearest(points.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = i + 1; j < points.size(); ++j) {
      const double d = squaredDistance(points[i], points[j]);
      nearest[i] = std::min(nearest[i], d);
      nearest[j] = std::min(nearest[j], d);
    }
  }
  const auto middle = nearest.begin() + nearest.size() / 2;
  std::nth_element(nearest.begin(), middle, nearest.end());
  return std::sqrt(*middle);
}

RbfInterpolant::RbfInterpolant(std::vector<FeaturePoint> centres, const RbfParams& params)
    : centres_(std::move(centres)), kernel_(params.kernel), polynomial_(params.polynomial) {
  std::string error;
  if (!params.isValid(&error)) throw ReconArgumentError(error);
  if (centres_.empty()) throw ReconArgumentError("RBF interpolation needs at least one centre");
  const std::size_t n = centres_.size();
  for (const FeaturePoint& c : centres_) {
    if (!std::all_of(c.begin(), c.end(), [](double x) { return std::isfinite(x); }))
      throw ReconArgumentError("RBF centre with a non-finite coordinate");
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (squaredDistance(centres_[i], centres_[j]) < 1e-18) {
        throw ReconArgumentError("RBF centres " + std::to_string(i) + " and " +
                                 std::to_string(j) + " coincide");
      }
    }
  }
  shapeRad_ =
      params.shapeRad.value_or(params.shapeScale * medianNearestNeighbourDistance(centres_));
  // A single centre has no neighbour; any positive r0 gives the same (constant) interpolant.
  if (!(shapeRad_ > 0.0)) shapeRad_ = 1.0;

  const std::size_t m = std::size_t(polynomialTerms());
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(n + m, n + m);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i; j < n; ++j)
      system(i, j) = system(j, i) = kernel(centres_[i], centres_[j]);
    system(i, n) = system(n, i) = 1.0;
    for (std::size_t k = 1; k < m; ++k)
      system(i, n + k) = system(n + k, i) = centres_[i][k - 1];
  }
  lu_.compute(system);
}

double RbfInterpolant::kernel(const FeaturePoint& a, const FeaturePoint& b) const {
  const double r2 = squaredDistance(a, b);
  switch (kernel_) {
    case RbfKernel::InverseMultiquadric:
      return 1.0 / std::sqrt(r2 + shapeRad_ * shapeRad_);
    case RbfKernel::Linear:
      return std::sqrt(r2);
    case RbfKernel::Cubic:
      return r2 * std::sqrt(r2);
    case RbfKernel::Multiquadric:
      break;
  }
  return std::sqrt(r2 + shapeRad_ * shapeRad_);
}

Eigen::MatrixXd RbfInterpolant::coefficients(const Eigen::MatrixXd& values) const {
  const auto n = static_cast<Eigen::Index>(centres_.size());
  if (values.rows() != n) {
    throw ReconArgumentError("RBF values have " + std::to_string(values.rows()) + " rows for " +
                             std::to_string(n) + " centres");
  }
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + polynomialTerms(), values.cols());
  rhs.topRows(n) = values;
  return lu_.solve(rhs);
}

Eigen::MatrixXf RbfInterpolant::evaluationMatrix(std::span<const FeaturePoint> points) const {
  const auto n = static_cast<Eigen::Index>(centres_.size());
  const int m = polynomialTerms();
  Eigen::MatrixXf rows(static_cast<Eigen::Index>(points.size()), n + m);
  for (std::size_t j = 0; j < points.size(); ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    for (Eigen::Index i = 0; i < n; ++i)
      rows(row, i) = static_cast<float>(kernel(points[j], centres_[i]));
    rows(row, n) = 1.0f;
    for (int k = 1; k < m; ++k)
      rows(row, n + k) = static_cast<float>(points[j][std::size_t(k - 1)]);
  }
  return rows;
}

double RbfInterpolant::evaluate(const Eigen::VectorXd& coefficients,
                                const FeaturePoint& point) const {
  const std::size_t n = centres_.size();
  double value = coefficients(static_cast<Eigen::Index>(n));
  for (int k = 1; k < polynomialTerms(); ++k)
    value += coefficients(static_cast<Eigen::Index>(n) + k) * point[std::size_t(k - 1)];
  for (std::size_t i = 0; i < n; ++i)
    value += coefficients(static_cast<Eigen::Index>(i)) * kernel(point, centres_[i]);
  return value;
}

std::size_t RbfInterpolant::memoryBytes() const {
  const std::size_t n = centres_.size() + std::size_t(polynomialTerms());
  return n * n * sizeof(double) + n * sizeof(int);
}

}  // namespace slicecap::recon
