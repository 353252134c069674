// Merging an azimuth bin's frames of an HDR sweep (several exposures) into one BRDF value.
#pragma once

#include <optional>
#include <vector>

#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::capture {

/// \brief A cell read darker than this fraction of full scale is left out when another frame of
/// the bin reads it brighter: 8-bit sRGB codes are coarse there (code 16), and the room light's
/// subtraction noisy.
inline constexpr double kHdrDarkFraction = 0.005;

/// \brief What the merge of one bin gives.
struct HdrMerge {
  Rgb value;             ///< linear BRDF, 1/sr
  int clippedCells = 0;  ///< cells clipped in every frame: their largest reading, a lower bound
};

/// \brief The BRDF of a bin from its frames' HDR readings (docs/method.md, HDR capture): per cell
/// and channel, the inverse-variance weighted mean of the frames' radiance (per unit exposure x
/// gain) over the frames where it is not clipped and, if any frame reads it above
/// kHdrDarkFraction, only those; the window radiance is the mean over cells; divided by the
/// frames' irradiance weighted by irradianceWeight. nullopt when a sample has no HDR reading or
/// the readings' cell counts differ (the caller then takes the median of the values).
std::optional<HdrMerge> mergeHdrBin(const std::vector<FrameSample>& samples);

}  // namespace slicecap::capture
