// Ceres problem set-up: one cost over all 19683 residuals (one dense Jacobian; per-pair blocks
// would cost Ceres 6561 block evaluations an iteration for nothing).
#include "start_solver.hpp"

#include <ceres/crs_matrix.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <cmath>
#include <memory>
#include <vector>

#include "material_cost.hpp"

namespace slicecap::fit::detail {
namespace {

// The alphas' range: below 0.002 the lobe is a mirror the grid's 15 deg steps cannot see; above
// 2 it is flatter than any rough surface. The sheen roughness as the Charlie lobe allows.
constexpr double kMinimumAlpha = 0.002, kMaximumAlpha = 2.0;
constexpr double kMinimumSheenRoughness = 0.05, kMaximumSheenRoughness = 1.0;

// The isotropic GGX block: 8 free directions of the 10 parameters. log alpha_t and log alpha_b
// take the same step (they start equal, so they stay equal; their bounds are the same, so a
// step clipped at a bound clips both alike) and the tangent none (a round lobe has no direction).
class IsotropicLobeManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kGgxParameters; }
  int TangentSize() const override { return kGgxParameters - 2; }
  bool Plus(const double* x, const double* delta, double* xPlusDelta) const override {
    for (int i = 0; i < kGgxParameters; ++i) xPlusDelta[i] = x[i];
    for (int i = 0; i < 6; ++i) xPlusDelta[i] += delta[i];
    xPlusDelta[6] += delta[6];
    xPlusDelta[7] += delta[6];
    xPlusDelta[9] += delta[7];
    return true;
  }
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    const int cols = TangentSize();
    for (int i = 0; i < kGgxParameters * cols; ++i) jacobian[i] = 0.0;
    for (int i = 0; i < 6; ++i) jacobian[i * cols + i] = 1.0;
    jacobian[6 * cols + 6] = 1.0;
    jacobian[7 * cols + 6] = 1.0;
    jacobian[9 * cols + 7] = 1.0;
    return true;
  }
  bool Minus(const double* y, const double* x, double* yMinusX) const override {
    for (int i = 0; i < 6; ++i) yMinusX[i] = y[i] - x[i];
    yMinusX[6] = 0.5 * ((y[6] - x[6]) + (y[7] - x[7]));
    yMinusX[7] = y[9] - x[9];
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    const int cols = kGgxParameters;
    for (int i = 0; i < TangentSize() * cols; ++i) jacobian[i] = 0.0;
    for (int i = 0; i < 6; ++i) jacobian[i * cols + i] = 1.0;
    jacobian[6 * cols + 6] = 0.5;
    jacobian[6 * cols + 7] = 0.5;
    jacobian[7 * cols + 9] = 1.0;
    return true;
  }
};

struct BuiltProblem {
  std::unique_ptr<ceres::Problem> problem;
  double* ggx;
  double* sheen;
  double* coat;
};

}  // namespace

void boundGgxBlock(ceres::Problem& problem, double* ggx) {
  for (int i = 0; i < 6; ++i) problem.SetParameterLowerBound(ggx, i, 0.0);
  for (int i = 3; i < 6; ++i) problem.SetParameterUpperBound(ggx, i, 1.0);
  problem.SetParameterLowerBound(ggx, 9, 0.0);
  problem.SetParameterUpperBound(ggx, 9, 1.0);
  for (int i = 6; i < 8; ++i) {
    problem.SetParameterLowerBound(ggx, i, std::log(kMinimumAlpha));
    problem.SetParameterUpperBound(ggx, i, std::log(kMaximumAlpha));
  }
}

namespace {

BuiltProblem buildProblem(const FitData& data, FitParameters& p) {
  BuiltProblem built{std::make_unique<ceres::Problem>(), p.ggx.data(),
                     p.withSheen ? p.sheen.data() : nullptr, p.withCoat ? p.coat.data() : nullptr};
  ceres::Problem& problem = *built.problem;
  std::vector<double*> blocks{built.ggx};
  if (p.withSheen) blocks.push_back(built.sheen);
  if (p.withCoat) blocks.push_back(built.coat);
  problem.AddResidualBlock(new MaterialCost(data, p.withSheen, p.withCoat), nullptr, blocks);
  boundGgxBlock(problem, built.ggx);
  if (p.isotropic) {
    p.ggx[7] = p.ggx[6];  // the manifold moves them together: they must start equal
    problem.SetManifold(built.ggx, new IsotropicLobeManifold);
  }
  if (p.withSheen) {
    for (int i = 0; i < 3; ++i) problem.SetParameterLowerBound(built.sheen, i, 0.0);
    problem.SetParameterLowerBound(built.sheen, 3, std::log(kMinimumSheenRoughness));
    problem.SetParameterUpperBound(built.sheen, 3, std::log(kMaximumSheenRoughness));
  }
  if (p.withCoat) {
    problem.SetParameterLowerBound(built.coat, 0, 0.0);
    problem.SetParameterUpperBound(built.coat, 0, 1.0);
    problem.SetParameterLowerBound(built.coat, 1, std::log(kMinimumAlpha));
    problem.SetParameterUpperBound(built.coat, 1, std::log(kMaximumAlpha));
  }
  return built;
}

}  // namespace

SolveOutcome solveFromStart(const FitData& data, const FitParameters& start, int maxIterations,
                            double functionTolerance, double initialTrustRegionRadius) {
  SolveOutcome outcome;
  outcome.parameters = start;
  BuiltProblem built = buildProblem(data, outcome.parameters);
  const ceres::Solver::Options options =
      solverOptions(maxIterations, functionTolerance, initialTrustRegionRadius);
  ceres::Solver::Summary summary;
  ceres::Solve(options, built.problem.get(), &summary);
  outcome.cost = summary.final_cost;
  outcome.iterations = static_cast<int>(summary.iterations.size());
  outcome.converged =
      summary.termination_type == ceres::CONVERGENCE && std::isfinite(summary.final_cost);
  outcome.message = summary.message;
  return outcome;
}

ceres::Solver::Options solverOptions(int maxIterations, double functionTolerance,
                                     double initialTrustRegionRadius) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = maxIterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  // Residuals are in 8-bit levels: a relative cost change of 1e-10 is far below what rounding to
  // 8 bits can show, so converged means settled, not merely slow.
  options.function_tolerance = functionTolerance;
  options.initial_trust_region_radius = initialTrustRegionRadius;
  options.parameter_tolerance = 1e-8;
  options.gradient_tolerance = 1e-12;
  return options;
}

Eigen::MatrixXd jacobianAt(const FitData& data, const FitParameters& parameters) {
  FitParameters p = parameters;
  p.isotropic = false;  // every parameter's column, the sigmas' indexing
  BuiltProblem built = buildProblem(data, p);
  ceres::CRSMatrix crs;
  built.problem->Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[static_cast<std::size_t>(row)];
         k < crs.rows[static_cast<std::size_t>(row) + 1]; ++k)
      jacobian(row, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];
  return jacobian;
}

}  // namespace slicecap::fit::detail
