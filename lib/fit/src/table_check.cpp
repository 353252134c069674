// A BRDF is finite and non-negative, and a material that reflects nothing has nothing to fit: each
// is refused by name, never fitted to a default.
#include "table_check.hpp"

#include <cmath>
#include <sstream>

#include "slicecap/fit/material_fit.hpp"

namespace slicecap::fit::detail {

void requireBrdf(const Abrdf& table, const std::string& name) {
  bool anyPositive = false;
  for (int l = 0; l < Abrdf::kDirections; ++l) {
    for (int v = 0; v < Abrdf::kDirections; ++v) {
      for (int c = 0; c < 3; ++c) {
        const float value = table.channel(l, v, c);
        if (!std::isfinite(value) || value < 0.0f) {
          std::ostringstream message;
          message << name << ": not a BRDF: value " << value << " at light " << l << ", view " << v
                  << ", channel " << "RGB"[c] << " (a BRDF is finite and non-negative)";
          throw FitError(message.str());
        }
        anyPositive = anyPositive || value > 0.0f;
      }
    }
  }
  if (!anyPositive)
    throw FitError(name + ": not a BRDF to fit: every value is zero (nothing reflects)");
}

}  // namespace slicecap::fit::detail
