// Levenberg-Marquardt with bounds that holds a parameter resting on its bound out of the steps.
//
// Why: Ceres keeps bounds by projecting each step onto the box. When a parameter's optimum lies
// beyond its bound (a lobe's Schlick f90 wanting more than 1, a Ward table's f90 or sheen colour
// wanting less than 0), every step computed as if it were free is cut back at the bound, the
// model's predicted decrease is not what the cut step gives (step quality ~0.07), the trust region
// shrinks and the solve crawls to its function tolerance: 20-30 iterations where 6-7 do
// (docs/results/2026-12-03-fit-speed.md). Here such a parameter is held where it is (a manifold
// without its direction), and let go again when the gradient at a solution says that moving it
// inward would lower the cost by more than the solver's own tolerance would notice (the
// Karush-Kuhn-Tucker check of an active-set method).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <ceres/cost_function.h>
#include <ceres/solver.h>

namespace slicecap::fit::detail {

/// \brief One parameter block of a bounded problem.
struct BoundedBlock {
  double* values = nullptr;
  std::vector<double> lower;  ///< per coordinate; -infinity where unbounded
  std::vector<double> upper;  ///< per coordinate; +infinity where unbounded
  /// \brief The block's directions of motion: each a set of coordinates that take the same step
  /// (an isotropic lobe's two log alphas). A coordinate in no set stays where it starts. The
  /// coordinates of one set must share their bounds.
  std::vector<std::vector<int>> moves;
  int size() const { return static_cast<int>(lower.size()); }
};

/// \brief A block of `size` coordinates, unbounded, each moving on its own.
BoundedBlock unboundedBlock(double* values, int size);

struct BoundedSolveSummary {
  bool converged = false;  ///< the last solve ended in CONVERGENCE (or had nothing free to move)
  double cost = 0.0;       ///< 1/2 sum of squared residuals at the end
  int iterations = 0;      ///< Levenberg-Marquardt iterations of every round
  int rounds = 0;          ///< solves run: 1 + the times the set of held directions changed
  std::string message;     ///< Ceres' account of the last solve
};

/// \brief Evaluates `cost` at `parameters` (one pointer a block, in the cost's order): its
/// residuals, and its Jacobian as one dense matrix (residuals x every block's coordinates, the
/// blocks side by side in that order). False when the cost's evaluation fails; the outputs are
/// then unspecified.
bool denseJacobian(const ceres::CostFunction& cost, const std::vector<const double*>& parameters,
                   Eigen::VectorXd& residuals, Eigen::MatrixXd& jacobian);

/// \brief Minimises 1/2 |r|^2 of `cost` over `blocks` (in the cost's block order) from their
/// current values, which must lie within their bounds, and leaves the solution in them.
/// `options` as for ceres::Solve; its max_num_iterations bounds all rounds together and its
/// initial trust region the first. A start outside its bounds is moved onto them. A direction
/// resting on a bound is held unless the Gauss-Newton model says that letting it go moves it
/// inward and lowers the cost by more than function_tolerance of it (one such direction is let go
/// per round); a direction that reaches a bound during a solve ends that solve and is held from
/// there. At most 12 rounds; the last runs as plain Ceres. Never throws for a bad fit: see
/// `converged`. Throws FitArgumentError for blocks that do not match `cost`.
BoundedSolveSummary solveHoldingBounds(const ceres::CostFunction& cost,
                                       std::vector<BoundedBlock>& blocks,
                                       ceres::Solver::Options options);

}  // namespace slicecap::fit::detail
