// The error lib/eval throws for tables it cannot compare.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::eval {

/// \brief Tables the metrics cannot compare (a reference without a positive value); the message
/// says why.
class EvalError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::eval
