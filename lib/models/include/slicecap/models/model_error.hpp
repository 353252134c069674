// The error lib/models throws for a model parameter it refuses.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::models {

/// \brief A reflectance model's parameter out of range; the message names the parameter.
class ModelError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::models
