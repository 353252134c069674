// An RBF spec (`--rbf SPEC`): Method A's open choices (docs/method.md §5.3), for a and uniform.
#pragma once

#include <string>

#include "slicecap/methods/methods.hpp"

namespace slicecap::methods {

/// \brief Applies "key=value,..." to options.rbf and options.onionFrame. Keys: kernel (mq, imq,
/// r, r3), poly (const, linear), r0 (a multiple of the median nearest-neighbour distance,
/// 0.01..4), frame (relative, absolute), gamma (the value domain v^(1/gamma); 1 = linear;
/// 1..1000). Throws MethodError ("--rbf: ...") naming the key or value that is unknown or out of
/// range (and the range): outside them the interpolant is lost to rounding.
void applyRbfSpec(const std::string& spec, MethodOptions& options);

/// \brief The options as a spec applyRbfSpec reads back, e.g. "kernel=r3,poly=linear,...".
std::string rbfSpec(const MethodOptions& options);

}  // namespace slicecap::methods
