// How a candidate model is searched for: every start scouted on a share of the pairs, then the
// most promising ones solved in full, the best converged one kept.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "fit_data.hpp"
#include "slicecap/fit/material_fit.hpp"
#include "start_solver.hpp"

namespace slicecap::fit::detail {

/// \brief Each start is first scouted on every kScoutStride-th pair for at most kScoutIterations
/// iterations (the basin shows by then; the tangent's basins are what the starts are for). Scouting
/// every start to convergence on all 6561 pairs cost 4x the time for the same answers on the
/// built-in materials.
inline constexpr int kScoutStride = 3;
inline constexpr int kScoutIterations = 8;

/// \brief One start and where its scouting solve ended.
struct Scout {
  FitParameters start;
  SolveOutcome outcome;
};

/// \brief Every start solved on `scoutData` for min(kScoutIterations, maxIterations) iterations,
/// the lowest cost first. Never throws for a bad fit (a scout that did not converge is still
/// ranked by its cost).
std::vector<Scout> scoutStarts(const FitData& scoutData, const std::vector<FitParameters>& starts,
                               int maxIterations);

/// \brief The best converged full solve (on `data`) of the most promising scouts: the best one, and
/// up to `maxPolished` in all of those within a cost factor of it that are not in its basin.
/// nullopt when none converged (`failure` then says how the best unconverged one ended) or when
/// `scouts` is empty. The candidate's metrics are against `table`; `startsTried` is scouts.size().
std::optional<CandidateFit> polishBest(const Abrdf& table, const FitData& data,
                                       const std::vector<Scout>& scouts, int maxIterations,
                                       std::size_t maxPolished, std::string& failure);

/// \brief polishBest(scoutStarts(...)).
std::optional<CandidateFit> bestOf(const Abrdf& table, const FitData& data,
                                   const FitData& scoutData,
                                   const std::vector<FitParameters>& starts, int maxIterations,
                                   std::size_t maxPolished, std::string& failure);

}  // namespace slicecap::fit::detail
