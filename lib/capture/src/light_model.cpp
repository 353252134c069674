// Ceres fit of a point light to reference radiances on the target plane.
#include "slicecap/capture/light_model.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/core/angles.hpp"

namespace slicecap::capture {
namespace {

// r = weight * ((albedo/pi) * I * z / |P - x|^3 / measured - 1): relative, so bright and dim
// areas count alike but for their noise (the weight).
struct ReferenceResidual {
  double x, y, z, albedo, measured, weight;

  template <typename T>
  bool operator()(const T* position, const T* logIntensity, T* residual) const {
    const T dx = position[0] - x, dy = position[1] - y, dz = position[2] - z;
    const T distanceSquared = dx * dx + dy * dy + dz * dz;
    const T irradiance = exp(logIntensity[0]) * dz / (distanceSquared * sqrt(distanceSquared));
    residual[0] =
        T(weight) * (T(albedo / std::numbers::pi) * irradiance / T(measured) - T(1.0));
    return true;
  }

  static ceres::CostFunction* Create(const ReferenceObservation& o, double weight) {
    return new ceres::AutoDiffCostFunction<ReferenceResidual, 1, 3, 1>(new ReferenceResidual{
        o.point.x, o.point.y, o.point.z, o.albedo.mean(), o.radiance.mean(), weight});
  }
};

// A weak pull of the LED position toward the nominal one, in units of the nominal distance.
struct PositionPrior {
  double nominal[3], weight;

  template <typename T>
  bool operator()(const T* position, T* residual) const {
    for (int k = 0; k < 3; ++k)
      residual[k] = T(weight) * (position[k] - T(nominal[k]));
    return true;
  }

  static ceres::CostFunction* Create(const TargetPointMm& p, double weight) {
    const double distance = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    return new ceres::AutoDiffCostFunction<PositionPrior, 3, 3>(
        new PositionPrior{{p.x, p.y, p.z}, weight / distance});
  }
};

double geometry(const TargetPointMm& led, const TargetPointMm& p) {
  const double dx = led.x - p.x, dy = led.y - p.y, dz = led.z - p.z;
  const double d2 = dx * dx + dy * dy + dz * dz;
  return dz / (d2 * std::sqrt(d2));
}

// The position's covariance, scaled by the residual variance, projected across the line of sight.
double directionSigmaDeg(ceres::Problem& problem, const double* position,
                         const ceres::Solver::Summary& summary, std::size_t observationCount) {
  ceres::Covariance::Options options;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks{{position, position}};
  double c[9];
  if (observationCount <= 4 || !covariance.Compute(blocks, &problem) ||
      !covariance.GetCovarianceBlock(position, position, c)) {
    return std::numeric_limits<double>::infinity();
  }
  const double residualVariance = 2.0 * summary.final_cost / double(observationCount - 4);
  const double distance =
      std::sqrt(position[0] * position[0] + position[1] * position[1] + position[2] * position[2]);
  const double u[3] = {position[0] / distance, position[1] / distance, position[2] / distance};
  double trace = 0.0, along = 0.0;
  for (int i = 0; i < 3; ++i) {
    trace += c[4 * i];
    for (int j = 0; j < 3; ++j)
      along += u[i] * c[3 * i + j] * u[j];
  }
  const double across = std::max(0.0, trace - along) * residualVariance;
  return radToDeg(std::sqrt(across) / distance);
}

// Why the observations cannot fix a light, or nullopt when there are 5 or more with positive,
// finite radiance and positive albedo, spread in both directions on the plane.
std::optional<std::string> observationsProblem(std::span<const ReferenceObservation> observations) {
  if (observations.size() < 5) return "light fit: needs at least 5 reference observations";
  double meanX = 0.0, meanY = 0.0;
  for (const ReferenceObservation& o : observations) {
    for (std::size_t c = 0; c < 3; ++c) {
      if (!(o.radiance[c] > 0.0) || !(o.albedo[c] > 0.0) || !std::isfinite(o.radiance[c]))
        return "light fit: reference radiance and albedo must be positive and finite";
    }
    meanX += o.point.x / double(observations.size());
    meanY += o.point.y / double(observations.size());
  }
  // Points on one line cannot fix a position in 3-D: require spread in both directions.
  double sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (const ReferenceObservation& o : observations) {
    sxx += (o.point.x - meanX) * (o.point.x - meanX);
    syy += (o.point.y - meanY) * (o.point.y - meanY);
    sxy += (o.point.x - meanX) * (o.point.y - meanY);
  }
  if (sxx * syy - sxy * sxy < 1e-6 * (sxx + syy) * (sxx + syy))
    return "light fit: the reference observations lie on one line";
  return std::nullopt;
}

// With every observation's noise known, each counts by its inverse relative sigma (of the
// channels' mean for the geometry), scaled to a mean square of 1 so that the prior keeps its
// meaning; else all alike.
std::vector<double> observationWeights(std::span<const ReferenceObservation> observations,
                                       bool weighted) {
  std::vector<double> weights(observations.size(), 1.0);
  if (weighted) {
    double sumSquares = 0.0;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      const Rgb& s = observations[i].sigma;
      const double meanSigma = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / 3.0;
      weights[i] = observations[i].radiance.mean() / meanSigma;
      sumSquares += weights[i] * weights[i];
    }
    for (double& w : weights)
      w *= std::sqrt(double(observations.size()) / sumSquares);
  }
  return weights;
}

// The Ceres fit of the position and the power; fills fit.light.positionMm, directionSigmaDeg,
// converged and message.
void solveLightPosition(std::span<const ReferenceObservation> observations,
                        const std::vector<double>& weights, const LightFitParams& params,
                        LightFit& fit) {
  double position[3] = {params.initialPositionMm.x, params.initialPositionMm.y,
                        params.initialPositionMm.z};
  // Start the power where the first observation is explained exactly.
  const ReferenceObservation& first = observations.front();
  double logIntensity = std::log(first.radiance.mean() * std::numbers::pi / first.albedo.mean() /
                                 geometry(params.initialPositionMm, first.point));
  ceres::Problem problem;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    problem.AddResidualBlock(ReferenceResidual::Create(observations[i], weights[i]), nullptr,
                             position, &logIntensity);
  }
  if (params.priorWeight > 0.0) {
    problem.AddResidualBlock(PositionPrior::Create(params.initialPositionMm, params.priorWeight),
                             nullptr, position);
  }
  problem.SetParameterLowerBound(position, 2, 1.0);  // the LED stays above the target
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = params.maxIterations;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  fit.light.positionMm = {position[0], position[1], position[2]};
  fit.directionSigmaDeg = directionSigmaDeg(problem, position, summary, observations.size());
  fit.converged = summary.termination_type == ceres::CONVERGENCE && summary.IsSolutionUsable();
  fit.message = summary.message;
}

// Per channel: radiance = albedo_c / pi * I_c * g(x), linear in I_c at the fitted position
// (least squares weighted by 1 / sigma^2 when the noise is known).
void fitChannelIntensities(std::span<const ReferenceObservation> observations, bool weighted,
                           PointLight& light) {
  const auto inverseVariance = [&](const ReferenceObservation& o, std::size_t c) {
    return weighted ? 1.0 / (o.sigma[c] * o.sigma[c]) : 1.0;
  };
  for (std::size_t c = 0; c < 3; ++c) {
    double numerator = 0.0, denominator = 0.0;
    for (const ReferenceObservation& o : observations) {
      const double a = o.albedo[c] / std::numbers::pi * geometry(light.positionMm, o.point);
      numerator += inverseVariance(o, c) * a * o.radiance[c];
      denominator += inverseVariance(o, c) * a * a;
    }
    light.intensity[c] = numerator / denominator;
  }
}

// Relative residuals r, their relative sigmas s = sigma / measured: plain and weighted RMS.
void measureResiduals(std::span<const ReferenceObservation> observations, bool weighted,
                      LightFit& fit) {
  double squaredRelative = 0.0, weightedSquares = 0.0, weightSum = 0.0;
  for (const ReferenceObservation& o : observations) {
    for (std::size_t c = 0; c < 3; ++c) {
      const double model = o.albedo[c] / std::numbers::pi * fit.light.irradianceAt(o.point)[c];
      const double r = model / o.radiance[c] - 1.0;
      const double w = weighted ? std::pow(o.radiance[c] / o.sigma[c], 2) : 1.0;
      squaredRelative += r * r;
      weightedSquares += w * r * r;
      weightSum += w;
    }
  }
  fit.relativeResidualRms = std::sqrt(squaredRelative / (3.0 * double(observations.size())));
  fit.weightedResidualRms = std::sqrt(weightedSquares / weightSum);
  fit.degreesOfFreedom = 3 * static_cast<int>(observations.size()) - 6;
  fit.noiseResidualRms = weighted ? std::sqrt(fit.degreesOfFreedom / weightSum) : 0.0;
}

}  // namespace

Rgb PointLight::irradianceAt(const TargetPointMm& point) const {
  return intensity * geometry(positionMm, point);
}

Direction PointLight::directionFrom(const TargetPointMm& point) const {
  return toDirection({positionMm.x - point.x, positionMm.y - point.y, positionMm.z - point.z});
}

bool LightFitParams::isValid(std::string* error) const {
  if (!(initialPositionMm.z > 0.0)) {
    if (error) *error = "the initial light position must be above the target (z > 0)";
    return false;
  }
  if (!(priorWeight >= 0.0)) {
    if (error) *error = "priorWeight must not be negative";
    return false;
  }
  if (maxIterations < 1) {
    if (error) *error = "maxIterations must be at least 1";
    return false;
  }
  return true;
}

std::optional<std::string> lightFitProblem(std::span<const ReferenceObservation> observations,
                                           const LightFitParams& params) {
  std::string error;
  if (!params.isValid(&error)) return "light fit: " + error;
  return observationsProblem(observations);
}

LightFit fitPointLight(std::span<const ReferenceObservation> observations,
                       const LightFitParams& params) {
  if (const std::optional<std::string> problem = lightFitProblem(observations, params))
    throw CaptureError(*problem);
  const bool weighted = std::all_of(observations.begin(), observations.end(), [](const auto& o) {
    return o.sigma.minChannel() > 0.0 && std::isfinite(o.sigma.maxChannel());
  });
  const std::vector<double> weights = observationWeights(observations, weighted);
  LightFit fit;
  solveLightPosition(observations, weights, params, fit);
  fitChannelIntensities(observations, weighted, fit.light);
  measureResiduals(observations, weighted, fit);
  return fit;
}

}  // namespace slicecap::capture
