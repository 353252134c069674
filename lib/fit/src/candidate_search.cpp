// Scouting every start cheaply, then solving the promising ones in full.
#include "candidate_search.hpp"

#include <algorithm>
#include <cmath>

#include "parameter_conversion.hpp"
#include "parameter_sigmas.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/eval/metrics.hpp"

namespace slicecap::fit::detail {
namespace {

// Scouts whose cost is within this factor of the best are solved in full too (how many is the
// caller's `maxPolished`: two for the GGX, the tangent's basins; one for the sheen, whose starts
// differ in the specular, which the scout has already settled: a second full solve doubled the
// velvet's time for the same answer).
constexpr double kPolishCostFactor = 1.25;

// Two scouts are in the same basin when their lobes agree in canonical form (alphas within 10 %,
// tangent within 5 deg): polishing both would find the same minimum twice.
bool sameBasin(const FitParameters& a, const FitParameters& b) {
  const FittedMaterial ma = materialOf(a), mb = materialOf(b);
  const auto near = [](double x, double y) { return std::abs(x / y - 1.0) < 0.1; };
  // A round lobe (both nearly isotropic) has no tangent to tell the two apart by.
  const bool round = ma.alphaTangent < 1.1 * ma.alphaBitangent &&
                     mb.alphaTangent < 1.1 * mb.alphaBitangent;
  return near(ma.alphaTangent, mb.alphaTangent) && near(ma.alphaBitangent, mb.alphaBitangent) &&
         (round || std::abs(tangentDifferenceDeg(ma.tangentDeg, mb.tangentDeg)) < 5.0);
}

}  // namespace

std::vector<Scout> scoutStarts(const FitData& scoutData, const std::vector<FitParameters>& starts,
                               int maxIterations) {
  std::vector<Scout> scouts;
  scouts.reserve(starts.size());
  for (const FitParameters& start : starts)
    scouts.push_back({start, solveFromStart(scoutData, start, std::min(kScoutIterations, maxIterations))});
  std::stable_sort(scouts.begin(), scouts.end(), [](const Scout& a, const Scout& b) {
    return a.outcome.cost < b.outcome.cost;
  });
  return scouts;
}

std::optional<CandidateFit> polishBest(const Abrdf& table, const FitData& data,
                                       const std::vector<Scout>& scouts, int maxIterations,
                                       std::size_t maxPolished, std::string& failure) {
  if (scouts.empty()) {
    failure = "no start";
    return std::nullopt;
  }
  const Scout& leader = scouts.front();
  std::optional<SolveOutcome> best, bestUnconverged;
  const Scout* bestScout = &leader;
  int converged = 0;
  for (std::size_t rank = 0; rank < scouts.size() && rank < maxPolished; ++rank) {
    const Scout& scout = scouts[rank];
    if (rank > 0 && !(scout.outcome.cost <= kPolishCostFactor * leader.outcome.cost)) break;
    if (rank > 0 && sameBasin(scout.outcome.parameters, leader.outcome.parameters)) continue;
    SolveOutcome outcome = solveFromStart(data, scout.outcome.parameters, maxIterations);
    outcome.iterations += scout.outcome.iterations;
    if (!outcome.converged) {
      if (!bestUnconverged || outcome.cost < bestUnconverged->cost) bestUnconverged = outcome;
      continue;
    }
    ++converged;
    if (!best || outcome.cost < best->cost) {
      best = std::move(outcome);
      bestScout = &scout;
    }
  }
  if (!best) {
    failure = bestUnconverged ? bestUnconverged->message : "no start";
    return std::nullopt;
  }
  CandidateFit candidate;
  candidate.material = materialOf(best->parameters);
  candidate.model = candidate.material.model;
  candidate.sigmas = parameterSigmas(data, *best, candidate.material);
  candidate.metrics = eval::compare(table, tabulate(candidate.material));
  candidate.cost = best->cost;
  candidate.iterations = best->iterations;
  candidate.startsTried = static_cast<int>(scouts.size());
  candidate.solvesConverged = converged;
  candidate.bestStartTangentDeg = radToDeg(bestScout->start.ggx[8]);
  candidate.isotropicLobe = bestScout->start.isotropic;
  return candidate;
}

std::optional<CandidateFit> bestOf(const Abrdf& table, const FitData& data,
                                   const FitData& scoutData,
                                   const std::vector<FitParameters>& starts, int maxIterations,
                                   std::size_t maxPolished, std::string& failure) {
  return polishBest(table, data, scoutStarts(scoutData, starts, maxIterations), maxIterations,
                    maxPolished, failure);
}

}  // namespace slicecap::fit::detail
