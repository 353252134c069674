// The slices of a set at chosen elevation pairs: a capture that swept only those.
#pragma once

#include <algorithm>
#include <vector>

#include "slicecap/core/slice.hpp"

namespace slicecap::test {

/// \brief Every sample of `all` whose slice is at one of `pairs`.
inline SliceSet keepPairs(const SliceSet& all, const std::vector<ElevationPair>& pairs) {
  SliceSet out;
  for (const Slice& s : all.slices()) {
    if (std::find(pairs.begin(), pairs.end(), s.id.elevations) == pairs.end()) continue;
    for (const SliceSample& sample : s.samples)
      out.add(s.id, sample);
  }
  return out;
}

}  // namespace slicecap::test
