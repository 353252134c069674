// Parameter uncertainty from the Jacobian at the solution.
#pragma once

#include "slicecap/fit/material_fit.hpp"
#include "start_solver.hpp"

namespace slicecap::fit::detail {

/// \brief The sigmas of `solution` (raw parameters) in the units of the canonical material
/// `canonicalMaterial`, which was made from it (the alphas' roles swap when canonical() swapped
/// them).
ParameterSigmas parameterSigmas(const FitData& data, const SolveOutcome& solution,
                                const FittedMaterial& canonicalMaterial);

}  // namespace slicecap::fit::detail
