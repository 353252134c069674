// The RBF interpolant: exact at its centres, exact for constants, checked inputs.
#include "slicecap/recon/rbf_interpolant.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

std::vector<FeaturePoint> randomPoints(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<FeaturePoint> points(count);
  for (FeaturePoint& p : points) {
    for (double& x : p)
      x = u(rng);
  }
  return points;
}

TEST(RbfInterpolant, ReproducesTheValuesAtItsCentres) {
  const std::vector<FeaturePoint> centres = randomPoints(60, 1);
  const RbfInterpolant rbf(centres);
  Eigen::MatrixXd values(60, 2);
  for (int i = 0; i < 60; ++i) {
    values(i, 0) = std::sin(centres[i][0]) + centres[i][3];
    values(i, 1) = std::exp(-centres[i][1] * centres[i][1]);
  }
  const Eigen::MatrixXd coefficients = rbf.coefficients(values);
  ASSERT_EQ(coefficients.rows(), 61);
  for (int i = 0; i < 60; ++i) {
    EXPECT_NEAR(rbf.evaluate(coefficients.col(0), centres[i]), values(i, 0), 1e-9);
    EXPECT_NEAR(rbf.evaluate(coefficients.col(1), centres[i]), values(i, 1), 1e-9);
  }
}

TEST(RbfInterpolant, ReproducesAConstantEverywhere) {
  const RbfInterpolant rbf(randomPoints(40, 2));
  const Eigen::MatrixXd coefficients = rbf.coefficients(Eigen::MatrixXd::Constant(40, 1, 0.7));
  for (const FeaturePoint& p : randomPoints(20, 3))
    EXPECT_NEAR(rbf.evaluate(coefficients.col(0), p), 0.7, 1e-9);
}

TEST(RbfInterpolant, EvaluationMatrixMatchesPointEvaluation) {
  const RbfInterpolant rbf(randomPoints(50, 4));
  Eigen::MatrixXd values = Eigen::MatrixXd::Random(50, 3);
  const Eigen::MatrixXd coefficients = rbf.coefficients(values);
  const std::vector<FeaturePoint> points = randomPoints(30, 5);
  const Eigen::MatrixXf rows = rbf.evaluationMatrix(points);
  ASSERT_EQ(rows.rows(), 30);
  ASSERT_EQ(rows.cols(), 51);
  const Eigen::MatrixXd product = rows.cast<double>() * coefficients;
  for (int j = 0; j < 30; ++j) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(product(j, c), rbf.evaluate(coefficients.col(c), points[j]), 1e-3);
  }
}

TEST(RbfInterpolant, ShapeDefaultsToTheMedianNearestNeighbourDistance) {
  // Points on a line, 0.1 apart except one gap of 0.5: the median nearest distance is 0.1.
  std::vector<FeaturePoint> points;
  for (double x : {0.0, 0.1, 0.2, 0.3, 0.8})
    points.push_back({x, 0, 0, 0});
  EXPECT_NEAR(medianNearestNeighbourDistance(points), 0.1, 1e-12);
  EXPECT_NEAR(RbfInterpolant(points).shapeRad(), 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(RbfInterpolant(points, {0.3}).shapeRad(), 0.3);
}

const std::array<RbfKernel, 4> kAllKernels{RbfKernel::Multiquadric, RbfKernel::InverseMultiquadric,
                                           RbfKernel::Linear, RbfKernel::Cubic};

TEST(RbfInterpolant, EveryKernelAndPolynomialReproducesItsCentres) {
  const std::vector<FeaturePoint> centres = randomPoints(60, 8);
  Eigen::MatrixXd values(60, 1);
  for (int i = 0; i < 60; ++i)
    values(i, 0) = std::sin(2 * centres[i][0]) * std::cos(centres[i][2]) + centres[i][1];
  for (RbfKernel kernel : kAllKernels) {
    for (RbfPolynomial polynomial : {RbfPolynomial::Constant, RbfPolynomial::Linear}) {
      RbfParams params;
      params.kernel = kernel;
      params.polynomial = polynomial;
      const RbfInterpolant rbf(centres, params);
      const Eigen::MatrixXd coefficients = rbf.coefficients(values);
      ASSERT_EQ(coefficients.rows(), 60 + polynomialTerms(polynomial));
      const Eigen::MatrixXf rows = rbf.evaluationMatrix(centres);
      const Eigen::MatrixXd atCentres = rows.cast<double>() * coefficients;
      for (int i = 0; i < 60; ++i) {
        EXPECT_NEAR(rbf.evaluate(coefficients.col(0), centres[i]), values(i, 0), 1e-8)
            << "kernel " << int(kernel) << ", polynomial " << int(polynomial);
        EXPECT_NEAR(atCentres(i, 0), values(i, 0), 1e-3) << "float evaluation rows";
      }
    }
  }
}

TEST(RbfInterpolant, TheLinearTermReproducesALinearFunctionEverywhere) {
  // Linear precision: extrapolation beyond the centres (Method A's 0/15 deg elevations) follows
  // a linear trend instead of falling back to the constant.
  const std::vector<FeaturePoint> centres = randomPoints(50, 9);
  auto linear = [](const FeaturePoint& x) {
    return 0.4 + 1.5 * x[0] - 0.7 * x[1] + 0.2 * x[2] + 2.0 * x[3];
  };
  Eigen::MatrixXd values(50, 1);
  for (int i = 0; i < 50; ++i)
    values(i, 0) = linear(centres[i]);
  std::vector<FeaturePoint> far = randomPoints(20, 10);
  for (FeaturePoint& p : far) {
    for (double& x : p)
      x *= 2.0;  // up to twice the centres' extent
  }
  for (RbfKernel kernel : kAllKernels) {
    RbfParams params;
    params.kernel = kernel;
    params.polynomial = RbfPolynomial::Linear;
    const RbfInterpolant rbf(centres, params);
    const Eigen::MatrixXd coefficients = rbf.coefficients(values);
    for (const FeaturePoint& p : far)
      EXPECT_NEAR(rbf.evaluate(coefficients.col(0), p), linear(p), 1e-7) << int(kernel);
  }
  // Without it, the multiquadric misses the linear function away from the centres.
  const RbfInterpolant constantOnly(centres);
  const Eigen::MatrixXd c = constantOnly.coefficients(values);
  double worst = 0.0;
  for (const FeaturePoint& p : far)
    worst = std::max(worst, std::abs(constantOnly.evaluate(c.col(0), p) - linear(p)));
  EXPECT_GT(worst, 0.01);
}

TEST(RbfInterpolant, ShapeScaleMultipliesTheMedianDistance) {
  std::vector<FeaturePoint> points;
  for (double x : {0.0, 0.1, 0.2, 0.3, 0.8})
    points.push_back({x, 0, 0, 0});
  RbfParams params;
  params.shapeScale = 2.5;
  EXPECT_NEAR(RbfInterpolant(points, params).shapeRad(), 0.25, 1e-12);
  params.shapeScale = 0.0;
  EXPECT_THROW(RbfInterpolant(points, params), recon::ReconArgumentError);
}

TEST(RbfInterpolant, RejectsInputsThatGiveNoInterpolant) {
  EXPECT_THROW(RbfInterpolant({}), recon::ReconArgumentError);
  EXPECT_THROW(RbfInterpolant({{0, 0, 0, 0}, {0, 0, 0, 0}}), recon::ReconArgumentError);
  EXPECT_THROW(RbfInterpolant({{0, 0, 0, NAN}}), recon::ReconArgumentError);
  EXPECT_THROW(RbfInterpolant(randomPoints(3, 6), {-1.0}), recon::ReconArgumentError);
  const RbfInterpolant rbf(randomPoints(3, 7));
  EXPECT_THROW(rbf.coefficients(Eigen::MatrixXd::Zero(4, 1)), recon::ReconArgumentError);
}

}  // namespace
}  // namespace slicecap::recon
