// The bounded Levenberg-Marquardt solve that holds directions resting on a bound
// (lib/fit/src/bounded_solve.cpp), on linear least squares whose box-constrained solution is
// found here by trying every set of active bounds.
#include "bounded_solve.hpp"

#include <gtest/gtest.h>

#include <ceres/cost_function.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "slicecap/fit/argument_error.hpp"

namespace slicecap::fit::detail {
namespace {

constexpr int kParameters = 3;

// r = A x - b over x = (block 0: x0, x1; block 1: x2).
class LinearCost final : public ceres::CostFunction {
 public:
  LinearCost(Eigen::MatrixXd a, Eigen::VectorXd b) : a_(std::move(a)), b_(std::move(b)) {
    set_num_residuals(int(a_.rows()));
    mutable_parameter_block_sizes()->assign({2, 1});
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Vector3d x(parameters[0][0], parameters[0][1], parameters[1][0]);
    Eigen::Map<Eigen::VectorXd>(residuals, a_.rows()) = a_ * x - b_;
    if (jacobians == nullptr) return true;
    for (Eigen::Index row = 0; row < a_.rows(); ++row) {
      if (jacobians[0]) {
        jacobians[0][2 * row] = a_(row, 0);
        jacobians[0][2 * row + 1] = a_(row, 1);
      }
      if (jacobians[1]) jacobians[1][row] = a_(row, 2);
    }
    return true;
  }

 private:
  Eigen::MatrixXd a_;
  Eigen::VectorXd b_;
};

// A well-conditioned A with correlated columns (so that holding one moves the others' optimum).
Eigen::MatrixXd someA() {
  Eigen::MatrixXd a(6, kParameters);
  a << 1.0, 0.3, 0.2,  //
      0.2, 1.0, 0.4,   //
      0.5, 0.1, 1.0,   //
      0.3, 0.8, 0.6,   //
      0.9, 0.4, 0.3,   //
      0.1, 0.2, 0.7;
  return a;
}

// b for which the unconstrained least-squares solution is `x`.
Eigen::VectorXd targetFor(const Eigen::MatrixXd& a, const Eigen::Vector3d& x) { return a * x; }

// The minimum of |A x - b|^2 over the box [lower, upper]^3, by trying each coordinate free, at
// its lower bound or at its upper bound (27 sets) and keeping the best feasible one.
Eigen::Vector3d boxSolution(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, double lower,
                            double upper) {
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double bestCost = std::numeric_limits<double>::infinity();
  for (int code = 0; code < 27; ++code) {
    std::array<int, kParameters> state{code % 3, (code / 3) % 3, code / 9};  // 0 free, 1 lo, 2 up
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    std::vector<int> free;
    for (int i = 0; i < kParameters; ++i) {
      if (state[std::size_t(i)] == 0) free.push_back(i);
      else x(i) = state[std::size_t(i)] == 1 ? lower : upper;
    }
    if (!free.empty()) {
      const Eigen::MatrixXd af = a(Eigen::all, free);
      const Eigen::VectorXd rest = b - a * x;
      const Eigen::VectorXd xf = af.colPivHouseholderQr().solve(rest);
      for (std::size_t k = 0; k < free.size(); ++k) x(free[k]) = xf(Eigen::Index(k));
    }
    if ((x.array() < lower - 1e-12).any() || (x.array() > upper + 1e-12).any()) continue;
    const double cost = (a * x - b).squaredNorm();
    if (cost < bestCost) {
      bestCost = cost;
      best = x;
    }
  }
  return best;
}

ceres::Solver::Options someOptions() {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.logging_type = ceres::SILENT;
  return options;
}

struct Problem {
  std::array<double, 2> first{};
  std::array<double, 1> second{};
  std::vector<BoundedBlock> blocks;
  Problem(Eigen::Vector3d start, double lower, double upper) {
    first = {start(0), start(1)};
    second = {start(2)};
    blocks = {unboundedBlock(first.data(), 2), unboundedBlock(second.data(), 1)};
    for (BoundedBlock& b : blocks) {
      b.lower.assign(b.lower.size(), lower);
      b.upper.assign(b.upper.size(), upper);
    }
  }
  Eigen::Vector3d x() const { return {first[0], first[1], second[0]}; }
};

TEST(BoundedSolve, HoldsTheDirectionsWhoseOptimumLiesBeyondTheirBounds) {
  const Eigen::MatrixXd a = someA();
  // Unconstrained optimum: x0 below 0, x2 above 1; x1's box optimum moves once they are held.
  const Eigen::VectorXd b = targetFor(a, {-0.4, 0.5, 1.6});
  const Eigen::Vector3d expected = boxSolution(a, b, 0.0, 1.0);
  ASSERT_DOUBLE_EQ(expected(0), 0.0);
  ASSERT_DOUBLE_EQ(expected(2), 1.0);
  ASSERT_GT(std::abs(expected(1) - 0.5), 0.05);  // the free one's optimum moved: a real test

  Problem p({0.5, 0.5, 0.5}, 0.0, 1.0);
  const LinearCost cost(a, b);
  const BoundedSolveSummary s = solveHoldingBounds(cost, p.blocks, someOptions());
  EXPECT_TRUE(s.converged) << s.message;
  EXPECT_GE(s.rounds, 2);  // a direction reached its bound in the first round and was held
  EXPECT_NEAR((p.x() - expected).norm(), 0.0, 1e-9) << p.x().transpose();
  EXPECT_NEAR(s.cost, 0.5 * (a * expected - b).squaredNorm(), 1e-12);
}

TEST(BoundedSolve, LetsGoOfABoundTheGradientPressesInward) {
  const Eigen::MatrixXd a = someA();
  const Eigen::Vector3d interior(0.3, 0.6, 0.2);
  const Eigen::VectorXd b = targetFor(a, interior);
  Problem p({0.0, 1.0, 1.0}, 0.0, 1.0);  // every coordinate starts on a bound
  const LinearCost cost(a, b);
  const BoundedSolveSummary s = solveHoldingBounds(cost, p.blocks, someOptions());
  EXPECT_TRUE(s.converged) << s.message;
  EXPECT_NEAR((p.x() - interior).norm(), 0.0, 1e-9) << p.x().transpose();
}

TEST(BoundedSolve, FindsTheBoxSolutionFromEveryCornerAndForManyTargets) {
  const Eigen::MatrixXd a = someA();
  int checked = 0;
  for (int t = 0; t < 27; ++t) {
    // Unconstrained optima below, inside and above the box in each coordinate.
    const Eigen::Vector3d target(-0.5 + 0.8 * (t % 3), -0.5 + 0.8 * ((t / 3) % 3),
                                 -0.5 + 0.8 * (t / 9));
    const Eigen::VectorXd b = targetFor(a, target);
    const Eigen::Vector3d expected = boxSolution(a, b, 0.0, 1.0);
    const LinearCost cost(a, b);
    for (int corner = 0; corner < 8; ++corner) {
      Problem p({double(corner & 1), double((corner >> 1) & 1), double((corner >> 2) & 1)}, 0.0,
                1.0);
      const BoundedSolveSummary s = solveHoldingBounds(cost, p.blocks, someOptions());
      ASSERT_TRUE(s.converged) << "target " << target.transpose() << " corner " << corner;
      // LM stops at a relative cost change of 1e-12: ~1e-7 from the minimum in x.
      ASSERT_NEAR((p.x() - expected).norm(), 0.0, 1e-6)
          << "target " << target.transpose() << " corner " << corner << ": " << p.x().transpose()
          << " (" << s.rounds << " rounds, " << s.iterations << " iterations: " << s.message << ")";
      ASSERT_NEAR(s.cost, 0.5 * (a * expected - b).squaredNorm(), 1e-10);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 27 * 8);
}

TEST(BoundedSolve, MovesGroupedCoordinatesTogetherAndLeavesUnlistedOnesWhereTheyStart) {
  const Eigen::MatrixXd a = someA();
  const Eigen::VectorXd b = targetFor(a, {0.2, 0.7, 0.4});
  Problem p({0.5, 0.5, 0.9}, -10.0, 10.0);
  p.blocks[0].moves = {{0, 1}};  // x0 and x1 take one step
  p.blocks[1].moves = {};        // x2 stays
  const LinearCost cost(a, b);
  const BoundedSolveSummary s = solveHoldingBounds(cost, p.blocks, someOptions());
  EXPECT_TRUE(s.converged) << s.message;
  EXPECT_DOUBLE_EQ(p.first[0], p.first[1]);
  EXPECT_DOUBLE_EQ(p.second[0], 0.9);
  // The one free direction's least squares: (a0 + a1) t = b - a2 x2.
  const Eigen::VectorXd column = a.col(0) + a.col(1);
  const double t = column.dot(b - 0.9 * a.col(2)) / column.squaredNorm();
  EXPECT_NEAR(p.first[0], t, 1e-9);
}

TEST(BoundedSolve, ReturnsAtOnceWhenEveryDirectionStaysOnItsBound) {
  const Eigen::MatrixXd a = someA();
  const Eigen::VectorXd b = targetFor(a, {-1.0, -1.0, -1.0});  // the box optimum is the corner 0
  ASSERT_NEAR(boxSolution(a, b, 0.0, 1.0).norm(), 0.0, 1e-12);
  Problem p({0.0, 0.0, 0.0}, 0.0, 1.0);
  const LinearCost cost(a, b);
  const BoundedSolveSummary s = solveHoldingBounds(cost, p.blocks, someOptions());
  EXPECT_TRUE(s.converged);
  EXPECT_EQ(s.rounds, 0);
  EXPECT_EQ(s.iterations, 0);
  EXPECT_NEAR(s.cost, 0.5 * b.squaredNorm(), 1e-12);
  EXPECT_EQ(p.x(), Eigen::Vector3d::Zero());
}

TEST(BoundedSolve, ItsRoundsShareOneIterationBudget) {
  const Eigen::MatrixXd a = someA();
  const Eigen::VectorXd b = targetFor(a, {-0.4, 0.5, 1.6});
  const Eigen::Vector3d expected = boxSolution(a, b, 0.0, 1.0);
  const LinearCost cost(a, b);
  int convergedWithin = 0;
  for (int budget = 1; budget <= 8; ++budget) {
    Problem p({0.5, 0.5, 0.5}, 0.0, 1.0);
    ceres::Solver::Options options = someOptions();
    options.max_num_iterations = budget;
    const BoundedSolveSummary s = solveHoldingBounds(cost, p.blocks, options);
    EXPECT_LE(s.iterations, budget) << s.rounds << " rounds";
    if (s.converged) {
      EXPECT_NEAR((p.x() - expected).norm(), 0.0, 1e-6) << "budget " << budget;
      if (convergedWithin == 0) convergedWithin = budget;
    }
  }
  EXPECT_GT(convergedWithin, 1);  // one iteration is not enough: the budget binds
}

// r_i = x1 exp(-x0 t_i) - y_i with y from x1 = 1.3, beyond x1's bound of 1: a nonlinear cost whose
// solution has x1 on its bound and x0 at the one-dimensional optimum with x1 = 1.
class DecayCost final : public ceres::CostFunction {
 public:
  DecayCost() {
    set_num_residuals(kSamples);
    mutable_parameter_block_sizes()->assign({2});
  }
  static double target(int i) { return 1.3 * std::exp(-0.7 * time(i)) + 0.02 * std::sin(3.0 * i); }
  static double time(int i) { return 0.25 * i; }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double rate = parameters[0][0], amplitude = parameters[0][1];
    for (int i = 0; i < kSamples; ++i) {
      const double decay = std::exp(-rate * time(i));
      residuals[i] = amplitude * decay - target(i);
      if (jacobians && jacobians[0]) {
        jacobians[0][2 * i] = -amplitude * time(i) * decay;
        jacobians[0][2 * i + 1] = decay;
      }
    }
    return true;
  }
  static constexpr int kSamples = 20;
};

// The rate minimising the cost with the amplitude at 1 (Newton on the one-dimensional cost).
double bestRateAtAmplitudeOne() {
  double rate = 0.5;
  for (int step = 0; step < 50; ++step) {
    double gradient = 0.0, curvature = 0.0;
    for (int i = 0; i < DecayCost::kSamples; ++i) {
      const double t = DecayCost::time(i), decay = std::exp(-rate * t);
      const double r = decay - DecayCost::target(i);
      gradient += r * (-t * decay);
      curvature += t * t * decay * decay + r * t * t * decay;
    }
    rate -= gradient / curvature;
  }
  return rate;
}

TEST(BoundedSolve, OnANonlinearCostItHoldsTheBoundAndFindsTheRestsOptimum) {
  const DecayCost cost;
  std::array<double, 2> x{0.3, 0.6};
  std::vector<BoundedBlock> blocks{unboundedBlock(x.data(), 2)};
  blocks[0].lower = {0.0, 0.0};
  blocks[0].upper = {5.0, 1.0};
  const BoundedSolveSummary s = solveHoldingBounds(cost, blocks, someOptions());
  EXPECT_TRUE(s.converged) << s.message;
  EXPECT_DOUBLE_EQ(x[1], 1.0);
  EXPECT_NEAR(x[0], bestRateAtAmplitudeOne(), 1e-6);
  EXPECT_LT(s.iterations, 20) << s.rounds << " rounds";
}

TEST(BoundedSolve, RefusesBlocksThatDoNotMatchTheCost) {
  const LinearCost cost(someA(), targetFor(someA(), {0.1, 0.1, 0.1}));
  std::array<double, 3> values{};
  std::vector<BoundedBlock> one{unboundedBlock(values.data(), 3)};
  EXPECT_THROW(solveHoldingBounds(cost, one, someOptions()), fit::FitArgumentError);
  std::vector<BoundedBlock> wrongSize{unboundedBlock(values.data(), 1),
                                      unboundedBlock(values.data() + 1, 1)};
  EXPECT_THROW(solveHoldingBounds(cost, wrongSize, someOptions()), fit::FitArgumentError);
}

}  // namespace
}  // namespace slicecap::fit::detail
