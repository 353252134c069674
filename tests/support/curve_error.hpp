// How far a fitted response curve is from the true one, as docs/linear-light.md measures it.
#pragma once

#include <algorithm>
#include <cmath>

#include "slicecap/core/tone_curve.hpp"

namespace slicecap::test {

/// The largest relative error of `fitted` against `truth` over linear lo..hi, either as the
/// values are (`scaled`: the fit's decode(1) = 1 rests on its extrapolation above the codes it
/// saw), or relative to their values at `hi` (the shape, which is what every ratio of two pixels
/// reads: the window over the white references, LED-on minus LED-off over the white).
inline double largestRelativeError(const ToneCurve& fitted, const ToneCurve& truth, double lo,
                                   double hi, bool scaled = false) {
  const double top = scaled ? 1.0 : fitted.decode(truth.encode(hi)) / hi;
  double worst = 0.0;
  for (int i = 0; i <= 200; ++i) {
    const double linear = lo * std::pow(hi / lo, i / 200.0);
    const double encoded = truth.encode(linear);
    worst = std::max(worst, std::abs(fitted.decode(encoded) / truth.decode(encoded) / top - 1.0));
  }
  return worst;
}

}  // namespace slicecap::test
