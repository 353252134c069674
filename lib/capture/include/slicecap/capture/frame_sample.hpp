// One accepted frame's measurement for the slice being swept.
#pragma once

#include <cstdint>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::capture {

/// \brief What one frame contributes: the BRDF of the window at the frame's actual light and view
/// directions (target frame, degrees), with where it came from.
struct FrameSample {
  std::int64_t timestampUs = 0;  ///< the frame's capture time
  std::uint64_t frameIndex = 0;  ///< position in its recording or stream
  Direction light;               ///< direction to the LED from the window centre
  Direction view;                ///< direction to the camera from the window centre
  Rgb value;                     ///< linear BRDF, 1/sr
};

}  // namespace slicecap::capture
