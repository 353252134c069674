// Multiquadric RBF interpolation with a constant term, factored once for a fixed set of centres.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "slicecap/recon/onion.hpp"

namespace slicecap::recon {

/// \brief Options of the interpolant (METHOD.md 5.2).
struct RbfParams {
  /// \brief r0 of the kernel sqrt(r^2 + r0^2), in feature-space radians; unset = the median
  /// nearest-neighbour distance among the centres (~0.26 rad on Method A's centres).
  std::optional<double> shapeRad;
  /// \brief The methods built on the interpolant (Method A, the uniform baseline) interpolate
  /// v^(1/valueGamma) and raise the result back. 1: linear BRDF values. 2.2: close to the 8-bit
  /// sRGB data the paper interpolated (METHOD.md 6.2), which compresses the highlights the
  /// multiquadric otherwise overshoots between elevations.
  double valueGamma = 1.0;
  /// \brief Returns false, with a reason, when shapeRad is set but not positive and finite, or
  /// valueGamma is not positive and finite.
  bool isValid(std::string* error) const;
};

/// \brief v^(1/gamma) of a value clipped to >= 0, and its inverse (clipped likewise).
double toInterpolatedValue(double value, double valueGamma);
double fromInterpolatedValue(double interpolated, double valueGamma);

/// \brief Median over the points of the distance to the nearest other point; 0 for fewer than
/// two points.
double medianNearestNeighbourDistance(std::span<const FeaturePoint> points);

/// \brief The interpolant through values at fixed centres: solve [K 1; 1^T 0] [w; c] = [y; 0]
/// once (LU with partial pivoting), then every channel, material or texture pixel costs two
/// triangular solves, and every evaluation point one row of kernel values.
class RbfInterpolant {
 public:
  /// \brief Factors the system. Throws std::invalid_argument for no centres, a non-finite
  /// coordinate, invalid params, or two centres closer than 1e-9 (the system would be singular).
  explicit RbfInterpolant(std::vector<FeaturePoint> centres, const RbfParams& params = {});

  std::size_t size() const { return centres_.size(); }
  const std::vector<FeaturePoint>& centres() const { return centres_; }
  /// \brief The r0 in use (given or derived).
  double shapeRad() const { return shapeRad_; }

  /// \brief sqrt(|a - b|^2 + r0^2).
  double kernel(const FeaturePoint& a, const FeaturePoint& b) const;

  /// \brief Coefficients, (n + 1) x k: the n centre weights, then the constant, for values n x k
  /// (one column per channel, material or pixel). Throws std::invalid_argument when values does
  /// not have n rows.
  Eigen::MatrixXd coefficients(const Eigen::MatrixXd& values) const;

  /// \brief Row j = (kernel(points[j], centre 1..n), 1): its product with coefficients() is the
  /// interpolant at the points. float, to halve the memory of large evaluation sets (the caller
  /// keeps the matrix when the points are fixed).
  Eigen::MatrixXf evaluationMatrix(std::span<const FeaturePoint> points) const;

  /// \brief The interpolant of one column of coefficients at one point, in double precision.
  double evaluate(const Eigen::VectorXd& coefficients, const FeaturePoint& point) const;

  /// \brief Bytes of the factorisation.
  std::size_t memoryBytes() const;

 private:
  std::vector<FeaturePoint> centres_;
  double shapeRad_ = 0.0;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace slicecap::recon
