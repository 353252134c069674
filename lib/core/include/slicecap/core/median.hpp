// The median of a set of values (an even count's middle two averaged): the robust centre the
// capture's bins, the window cells' texture rule and the decoding watch each read.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace slicecap {

/// \brief The median of `values` (taken by value: reordered in place); an even count's middle two
/// averaged. `values` must not be empty.
inline double median(std::vector<double> values) {
  const auto middle = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (values.size() % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(values.begin(), middle));
}

}  // namespace slicecap
