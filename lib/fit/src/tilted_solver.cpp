// The tilted solve: one cost over all residuals, two parameter blocks, bounds held as the table fit's.
#include "tilted_solver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "tilted_lobe.hpp"

namespace slicecap::fit::detail {

TiltedOutcome solveTiltedFromStart(const FitData& data, const TiltedParameters& start,
                                   int maxIterations, double functionTolerance,
                                   double initialTrustRegionRadius) {
  TiltedOutcome outcome;
  outcome.parameters = start;
  double* ggx = outcome.parameters.ggx.data();
  double* tilt = outcome.parameters.tilt.data();
  std::vector<BoundedBlock> blocks{ggxBlock(ggx, false), unboundedBlock(tilt, kTiltParameters)};
  blocks[1].lower.assign(kTiltParameters, -kMaximumTiltComponent);
  blocks[1].upper.assign(kTiltParameters, kMaximumTiltComponent);
  const TiltedCost cost(data);
  const BoundedSolveSummary summary = solveHoldingBounds(
      cost, blocks, solverOptions(maxIterations, functionTolerance, initialTrustRegionRadius));
  outcome.cost = summary.cost;
  outcome.converged = summary.converged;
  return outcome;
}

TiltedParameters withTilt(const FitParameters& p, const std::array<double, kTiltParameters>& tilt) {
  return {p.ggx, tilt};
}

FitParameters withoutTilt(const TiltedParameters& p) {
  FitParameters flat;
  flat.ggx = p.ggx;
  return flat;
}

TiltedParameters canonicalTilted(TiltedParameters p) {
  if (p.ggx[6] >= p.ggx[7]) return p;
  std::swap(p.ggx[6], p.ggx[7]);
  const TiltedFrame<double> f =
      tiltedFrame(std::cos(p.ggx[8]), std::sin(p.ggx[8]), p.tilt[0], p.tilt[1]);
  // Back along n' from the bitangent to the untilted plane z = 0: its projection is the bitangent.
  const double back = -f.bz / f.nz;
  p.ggx[8] = std::atan2(f.by + back * f.ny, f.bx + back * f.nx);
  return p;
}

UnitVector shadingNormalOf(const std::array<double, kTiltParameters>& tilt) {
  return {tilt[0], tilt[1], std::sqrt(std::max(0.0, 1.0 - tilt[0] * tilt[0] - tilt[1] * tilt[1]))};
}

bool lobeLocatesTilt(const std::array<double, kGgxParameters>& ggx) {
  const double f0 = std::max({ggx[3], ggx[4], ggx[5]});
  const double peak = f0 / (4.0 * std::numbers::pi * std::exp(ggx[6]) * std::exp(ggx[7]));
  const double diffuse = std::max({ggx[0], ggx[1], ggx[2]}) / std::numbers::pi;
  return peak > 0.0 && peak >= kMinimumLobeToDiffuse * diffuse;
}

double tiltedRmseLevels(const FitData& data, const TiltedParameters& p) {
  const TiltedCost cost(data);
  std::vector<double> residuals(static_cast<std::size_t>(data.residualCount()));
  const double* blocks[2] = {p.ggx.data(), p.tilt.data()};
  cost.Evaluate(blocks, residuals.data(), nullptr);
  double sum = 0.0;
  for (double r : residuals)
    sum += r * r;
  return std::sqrt(sum / static_cast<double>(residuals.size()));
}

}  // namespace slicecap::fit::detail
