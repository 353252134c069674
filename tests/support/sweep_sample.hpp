// A sweep sample at a slice parameter, as the session-store tests record and replay them.
#pragma once

#include <cstdint>

#include "slicecap/capture/frame_sample.hpp"

namespace slicecap::test {

/// \brief A grey sample of `value` at elevation 30/30, light azimuth `parameterDeg`, view 15 deg
/// beyond it, from frame `frame` (33 ms apart).
inline capture::FrameSample sampleAt(double parameterDeg, double value, std::uint64_t frame = 0) {
  return {std::int64_t(frame) * 33000,
          frame,
          {30, parameterDeg},
          {30, parameterDeg + 15},
          Rgb::gray(value)};
}

}  // namespace slicecap::test
