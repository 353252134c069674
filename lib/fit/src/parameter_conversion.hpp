// Between the solver's parameter blocks and a FittedMaterial (shared by the table fit and the
// texture fit's warm starts).
#pragma once

#include "slicecap/fit/fitted_material.hpp"
#include "start_solver.hpp"

namespace slicecap::fit::detail {

/// \brief The material of a solution, in the canonical convention.
FittedMaterial materialOf(const FitParameters& p);

/// \brief The GGX block of a material (its sheen, if any, dropped): a start for a solve.
FitParameters ggxParametersOf(const FittedMaterial& m);

/// \brief RMS residual of `p` on `data`, 8-bit sRGB levels (sqrt(2 cost / residuals)).
double rmseLevels(const FitData& data, const FitParameters& p);

}  // namespace slicecap::fit::detail
