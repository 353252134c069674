// Refusing a table that is not a BRDF before fitting it.
#pragma once

#include <string>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::fit::detail {

/// \brief Throws FitError "NAME: ..." for the first negative or non-finite value (its light, view
/// and channel) or for a table with no positive value (all zero: nothing reflects).
void requireBrdf(const Abrdf& table, const std::string& name);

}  // namespace slicecap::fit::detail
