// RBF interpolation (multiquadric by default) with a polynomial term, factored once for a fixed set
// of centres.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "slicecap/recon/onion.hpp"

namespace slicecap::recon {

/// \brief The radial function phi(r) (docs/method.md §5.2 leaves it open; SRC-8 found the first three
/// about equal on synthetic data).
enum class RbfKernel {
  Multiquadric,         ///< sqrt(r^2 + r0^2), Numerical Recipes' default
  InverseMultiquadric,  ///< 1 / sqrt(r^2 + r0^2)
  Linear,               ///< r (polyharmonic, no r0)
  Cubic,                ///< r^3 (polyharmonic, no r0; needs the linear polynomial term)
};

/// \brief The polynomial added to the radial sum, with its orthogonality conditions.
enum class RbfPolynomial {
  Constant,  ///< c: reproduces constants
  Linear,    ///< c + g . x: reproduces linear functions of the features (linear precision)
};

/// \brief Options of the interpolant (docs/method.md §5.2).
struct RbfParams {
  /// \brief r0 of the kernel sqrt(r^2 + r0^2), in feature-space radians; unset = the median
  /// nearest-neighbour distance among the centres (~0.26 rad on Method A's centres).
  std::optional<double> shapeRad;
  /// \brief The methods built on the interpolant (Method A, the uniform baseline) interpolate
  /// v^(1/valueGamma) and raise the result back. 1: linear BRDF values. 2.2: close to the 8-bit
  /// sRGB data the paper interpolated (docs/method.md §6.2), which compresses the highlights the
  /// multiquadric otherwise overshoots between elevations.
  double valueGamma = 1.0;
  RbfKernel kernel = RbfKernel::Multiquadric;
  RbfPolynomial polynomial = RbfPolynomial::Constant;
  /// \brief With shapeRad unset, r0 = shapeScale x the median nearest-neighbour distance.
  double shapeScale = 1.0;
  /// \brief Returns false, with a reason, when shapeRad is set but not positive and finite, or
  /// valueGamma or shapeScale is not positive and finite.
  bool isValid(std::string* error) const;
};

/// \brief v^(1/gamma) of a value clipped to >= 0, and its inverse (clipped likewise).
double toInterpolatedValue(double value, double valueGamma);
double fromInterpolatedValue(double interpolated, double valueGamma);

/// \brief Median over the points of the distance to the nearest other point; 0 for fewer than
/// two points.
double medianNearestNeighbourDistance(std::span<const FeaturePoint> points);

/// \brief Columns of the polynomial term: 1 (constant) or 5 (1 and the four features).
int polynomialTerms(RbfPolynomial polynomial);

/// \brief The interpolant through values at fixed centres: solve [K P; P^T 0] [w; c] = [y; 0]
/// (P: the polynomial's columns at the centres) once (LU with partial pivoting), then every
/// channel, material or texture pixel costs two triangular solves, and every evaluation point one
/// row of kernel values.
class RbfInterpolant {
 public:
  /// \brief Factors the system. Throws ReconArgumentError for no centres, a non-finite
  /// coordinate, invalid params, or two centres closer than 1e-9 (the system would be singular).
  explicit RbfInterpolant(std::vector<FeaturePoint> centres, const RbfParams& params = {});

  std::size_t size() const { return centres_.size(); }
  const std::vector<FeaturePoint>& centres() const { return centres_; }
  /// \brief The r0 in use (given or derived).
  double shapeRad() const { return shapeRad_; }

  /// \brief phi(|a - b|) of the params' kernel.
  double kernel(const FeaturePoint& a, const FeaturePoint& b) const;
  /// \brief Columns of the polynomial term (1 or 5).
  int polynomialTerms() const { return recon::polynomialTerms(polynomial_); }

  /// \brief Coefficients, (n + m) x k: the n centre weights, then the m polynomial coefficients
  /// (constant first, then the four linear ones), for values n x k
  /// (one column per channel, material or pixel). Throws ReconArgumentError when values does
  /// not have n rows.
  Eigen::MatrixXd coefficients(const Eigen::MatrixXd& values) const;

  /// \brief Row j = (kernel(points[j], centre 1..n), 1[, points[j]]): its product with
  /// coefficients() is the interpolant at the points. float, to halve the memory of large
  /// evaluation sets (the caller keeps the matrix when the points are fixed).
  Eigen::MatrixXf evaluationMatrix(std::span<const FeaturePoint> points) const;

  /// \brief The interpolant of one column of coefficients at one point, in double precision.
  double evaluate(const Eigen::VectorXd& coefficients, const FeaturePoint& point) const;

  /// \brief Bytes of the factorisation.
  std::size_t memoryBytes() const;

 private:
  std::vector<FeaturePoint> centres_;
  double shapeRad_ = 0.0;
  RbfKernel kernel_ = RbfKernel::Multiquadric;
  RbfPolynomial polynomial_ = RbfPolynomial::Constant;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace slicecap::recon
