// The error lib/fit throws for arguments it refuses.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::fit {

/// \brief Arguments lib/fit refuses (no start or iteration, rows of the wrong size, a cost whose
/// blocks do not match): a caller's mistake. Unlike FitError (material_fit.hpp), which says a fit
/// failed and which the texture fit catches per texel, it is not caught on the way.
class FitArgumentError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::fit
