// The elevation lobe fitted by Ceres' TinySolver (Levenberg-Marquardt over every sample; log k, n).
#include "slicecap/recon/lafortune_fit.hpp"

#include <ceres/tiny_solver.h>
#include <ceres/tiny_solver_cost_function_adapter.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "slicecap/core/angles.hpp"
#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/lobe_cost.hpp"

namespace slicecap::recon {
namespace {

template <typename Status>
std::string statusText(Status status) {
  switch (status) {
    case Status::GRADIENT_TOO_SMALL:
      return "converged: gradient below tolerance";
    case Status::RELATIVE_STEP_SIZE_TOO_SMALL:
      return "converged: step below tolerance";
    case Status::COST_TOO_SMALL:
      return "converged: cost below threshold";
    case Status::COST_CHANGE_TOO_SMALL:
      return "converged: cost change below tolerance";
    case Status::HIT_MAX_ITERATIONS:
      return "not converged: hit the iteration limit";
  }
  return "unknown status";
}

}  // namespace

LobeCost::LobeCost(std::span<const ElevationSample> samples, double minimumValue) {
  std::map<double, int> groupOfElevation;
  std::vector<std::pair<double, int>> sums;  // (sum, count) a group
  for (const ElevationSample& s : samples) {
    const auto [it, added] = groupOfElevation.try_emplace(s.thetaDeg, int(sums.size()));
    if (added) sums.push_back({0.0, 0});
    sums[it->second].first += std::max(s.value, minimumValue);
    ++sums[it->second].second;
    groupOf_.push_back(it->second);
    values_.push_back(std::max(s.value, minimumValue));
  }
  if (groupOfElevation.size() < 2)
    throw ReconArgumentError("lobe fit: needs samples at two distinct elevations");
  logCosLow_ = std::log(std::cos(degToRad(groupOfElevation.begin()->first)));
  logCosSpan_ = std::log(std::cos(degToRad(groupOfElevation.rbegin()->first))) - logCosLow_;
  groups_.resize(sums.size());
  for (const auto& [thetaDeg, g] : groupOfElevation) {
    groups_[g] = {(std::log(std::cos(degToRad(thetaDeg))) - logCosLow_) / logCosSpan_,
                  sums[g].second / sums[g].first};
  }
  set_num_residuals(static_cast<int>(samples.size()));
  mutable_parameter_block_sizes()->assign({2});
}

bool LobeCost::Evaluate(double const* const* parameters, double* residuals,
                        double** jacobians) const {
  const double a = parameters[0][0];
  const double b = parameters[0][1];
  // Per group: the weighted model and its derivatives by a and b.
  std::vector<std::array<double, 3>> perGroup(groups_.size());
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const double t = groups_[g].position, w = groups_[g].weight;
    const double m = std::exp((1.0 - t) * a + t * b);
    perGroup[g][0] = m * w;
    perGroup[g][1] = m * (1.0 - t) * w;
    perGroup[g][2] = m * t * w;
  }
  double* jacobian = jacobians ? jacobians[0] : nullptr;  // row-major, residuals x 2
  for (std::size_t i = 0; i < values_.size(); ++i) {
    const std::array<double, 3>& group = perGroup[groupOf_[i]];
    residuals[i] = group[0] - values_[i] * groups_[groupOf_[i]].weight;
    if (jacobian) {
      jacobian[2 * i] = group[1];
      jacobian[2 * i + 1] = group[2];
    }
  }
  return std::isfinite(residuals[0]);
}

ElevationLobe LobeCost::lobe(const double* parameters) const {
  const double n = (parameters[1] - parameters[0]) / logCosSpan_;
  return {std::exp(parameters[0] - n * logCosLow_), n};
}

double ElevationLobe::shape(double thetaDeg) const {
  return std::pow(std::cos(degToRad(thetaDeg)), n);
}

double ElevationLobe::operator()(double thetaDeg) const {
  return k * shape(thetaDeg);
}

bool LobeFitParams::isValid(std::string* error) const {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (!std::isfinite(initialN)) return fail("initialN must be finite");
  if (maxIterations < 1) return fail("maxIterations must be at least 1");
  if (!(minimumValue > 0.0)) return fail("minimumValue must be positive");
  return true;
}

LobeFitResult fitElevationLobe(std::span<const ElevationSample> samples,
                               const LobeFitParams& params) {
  std::string error;
  if (!params.isValid(&error)) throw ReconArgumentError("lobe fit: " + error);
  double meanValue = 0.0;
  for (const ElevationSample& s : samples) {
    // Said apart: a slice value too large for the sums (e.g. 1e300) overflows to inf here.
    if (!std::isfinite(s.value))
      throw ReconArgumentError("lobe fit: a sample value is not finite (" +
                               std::to_string(s.value) +
                               "): a slice value is too large or not a number");
    if (!std::isfinite(s.thetaDeg) || s.thetaDeg < 0.0 || s.thetaDeg >= 90.0) {
      throw ReconArgumentError("lobe fit: sample outside 0 <= theta < 90 deg or not finite");
    }
    meanValue += std::max(s.value, params.minimumValue) / double(samples.size());
  }
  const LobeCost cost(samples, params.minimumValue);
  const ceres::TinySolverCostFunctionAdapter<Eigen::Dynamic, 2> function(cost);
  ceres::TinySolver<ceres::TinySolverCostFunctionAdapter<Eigen::Dynamic, 2>> solver;
  solver.options.max_num_iterations = params.maxIterations;
  // TinySolver's cost-change test is absolute, so a dark group's tiny share of the cost could end
  // the solve early; steps and gradients judge convergence instead.
  solver.options.function_tolerance = 0.0;
  solver.options.parameter_tolerance = 1e-12;
  solver.options.gradient_tolerance = 1e-16;
  // The paper's constant start: k = 1 on the data's own scale (its mean), n = initialN.
  Eigen::Vector2d parameters(std::log(meanValue) + params.initialN * cost.lowLogCos(),
                             std::log(meanValue) + params.initialN * cost.highLogCos());
  const auto& summary = solver.Solve(function, &parameters);

  LobeFitResult result;
  result.lobe = cost.lobe(parameters.data());
  result.converged = summary.status != decltype(solver)::HIT_MAX_ITERATIONS &&
                     std::isfinite(result.lobe.k) && std::isfinite(result.lobe.n) &&
                     std::isfinite(summary.final_cost);
  result.iterations = summary.iterations;
  result.finalCost = summary.final_cost;
  result.message = statusText(summary.status);
  return result;
}

ElevationLobe closedFormLobe(double theta1Deg, double mean1, double theta2Deg, double mean2,
                             double minimumValue) {
  const double mu1 = std::max(mean1, minimumValue);
  const double mu2 = std::max(mean2, minimumValue);
  const double c1 = std::cos(degToRad(theta1Deg));
  const double c2 = std::cos(degToRad(theta2Deg));
  const double n = std::log(mu1 / mu2) / std::log(c1 / c2);
  return {mu1 / std::pow(c1, n), n};
}

}  // namespace slicecap::recon
