// The error lib/sim throws for a virtual rig it cannot build.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::sim {

/// \brief A renderer, rig or scene lib/sim cannot build from its parameters; the message names
/// them. A material specification it cannot read is the narrower MaterialError (material.hpp),
/// which the CLI reports as bad usage.
class SimError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::sim
