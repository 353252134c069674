// Ceres problem set-up: one cost over all 19683 residuals (one dense Jacobian; per-pair blocks
// would cost Ceres 6561 block evaluations an iteration for nothing).
#include "start_solver.hpp"

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

}  // namespace

BoundedBlock ggxBlock(double* ggx, bool isotropic) {
  BoundedBlock block = unboundedBlock(ggx, kGgxParameters);
  for (int i = 0; i < 6; ++i) block.lower[std::size_t(i)] = 0.0;
  for (int i = 3; i < 6; ++i) block.upper[std::size_t(i)] = 1.0;
  block.lower[9] = 0.0;
  block.upper[9] = 1.0;
  for (std::size_t i = 6; i < 8; ++i) {
    block.lower[i] = std::log(kMinimumAlpha);
    block.upper[i] = std::log(kMaximumAlpha);
  }
  if (isotropic) {
    // log alpha_t and log alpha_b take the same step (they start equal, so they stay equal; their
    // bounds are the same, so a step clipped at a bound clips both alike) and the tangent none (a
    // round lobe has no direction).
    ggx[7] = ggx[6];
    block.moves = {{0}, {1}, {2}, {3}, {4}, {5}, {6, 7}, {9}};
  }
  return block;
}

namespace {

std::vector<BoundedBlock> boundedBlocks(FitParameters& p) {
  std::vector<BoundedBlock> blocks{ggxBlock(p.ggx.data(), p.isotropic)};
  // A khr-form sheen fit is meant to be what a glTF viewer renders: its lobe stays within
  // KHR_materials_anisotropy's reach (alpha <= 1). Without the bound velvet-red's fit spent a
  // lobe of alpha 1.3 on its grazing sheen, which the export then had to clamp.
  if (p.withSheen && p.sheenForm == SheenForm::Khr)
    for (std::size_t i = 6; i < 8; ++i) blocks.front().upper[i] = 0.0;  // log 1
  if (p.withSheen) {
    BoundedBlock sheen = unboundedBlock(p.sheen.data(), kSheenParameters);
    for (std::size_t i = 0; i < 3; ++i) sheen.lower[i] = 0.0;
    // KHR_materials_sheen's sheenColorFactor is at most 1 (and the base's scaling 1 - s E stays
    // positive); the additive form has no such limit.
    if (p.sheenForm == SheenForm::Khr)
      for (std::size_t i = 0; i < 3; ++i) sheen.upper[i] = 1.0;
    sheen.lower[3] = std::log(kMinimumSheenRoughness);
    sheen.upper[3] = std::log(kMaximumSheenRoughness);
    blocks.push_back(std::move(sheen));
  }
  if (p.withCoat) {
    BoundedBlock coat = unboundedBlock(p.coat.data(), kCoatParameters);
    coat.lower = {0.0, std::log(kMinimumAlpha)};
    coat.upper = {1.0, std::log(kMaximumAlpha)};
    blocks.push_back(std::move(coat));
  }
  return blocks;
}

}  // namespace

SolveOutcome solveFromStart(const FitData& data, const FitParameters& start, int maxIterations,
                            double functionTolerance, double initialTrustRegionRadius) {
  SolveOutcome outcome;
  outcome.parameters = start;
  std::vector<BoundedBlock> blocks = boundedBlocks(outcome.parameters);
  const MaterialCost cost(data, start.withSheen, start.withCoat, start.sheenForm);
  const BoundedSolveSummary summary = solveHoldingBounds(
      cost, blocks, solverOptions(maxIterations, functionTolerance, initialTrustRegionRadius));
  outcome.cost = summary.cost;
  outcome.iterations = summary.iterations;
  outcome.converged = summary.converged;
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
  const MaterialCost cost(data, parameters.withSheen, parameters.withCoat, parameters.sheenForm);
  std::vector<const double*> blocks{parameters.ggx.data()};
  if (parameters.withSheen) blocks.push_back(parameters.sheen.data());
  if (parameters.withCoat) blocks.push_back(parameters.coat.data());
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;
  if (!denseJacobian(cost, blocks, residuals, jacobian))
    return Eigen::MatrixXd::Zero(data.residualCount(), parameters.count());
  return jacobian;
}

}  // namespace slicecap::fit::detail
