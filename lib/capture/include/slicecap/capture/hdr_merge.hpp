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

/// \brief The window centre's value replaces the cells' mean when the two differ by more than this
/// many standard deviations of their difference under noise (docs/method.md 9.3): a lobe that
/// curves across the sample square, not noise.
inline constexpr double kHdrCurvatureSigmas = 3.0;

/// \brief The centre's value from the cells' surface needs this many cells not clipped in every
/// frame (of kHdrCellsPerSide^2), the four around the centre among them.
inline constexpr int kHdrMinCurveCells = 12;

/// \brief Frames of a bin agree on a cell when they differ by no more than noise and this fraction
/// of the value (irradiance fit, room light, registration: as the white references' margin).
inline constexpr double kHdrSystematicFraction = 0.05;

/// \brief What the merge of one bin gives.
struct HdrMerge {
  Rgb value;             ///< linear BRDF, 1/sr
  int clippedCells = 0;  ///< cells clipped in every frame: their largest reading, a lower bound
  bool centreFromCurve = false;  ///< the value is the cells' quadratic surface at the centre
};

/// \brief The BRDF of a bin from its frames' HDR readings (docs/method.md, HDR capture): per cell
/// and channel, the inverse-variance weighted mean of the frames' radiance (per unit exposure x
/// gain) over the frames where it is not clipped and, if any frame reads it above
/// kHdrDarkFraction, only those; the window radiance is the mean over cells or, when the cells
/// not clipped in every frame curve across the square beyond noise (kHdrCurvatureSigmas) or some
/// cell is clipped in every frame (the mean a lower bound) and the surface is brighter, the
/// least-squares quadratic surface's value at the window centre; divided by the
/// frames' irradiance weighted by irradianceWeight. nullopt when a sample has no HDR reading or
/// the readings' cell counts differ (the caller then takes the median of the values).
/// `offCentreDeg` (one per sample, else all taken as 0): each frame's slice parameter minus the
/// bin's centre; where a cell's frames disagree beyond noise and kHdrSystematicFraction (or a
/// frame that clips it reads it brighter than the others' merge), they see different values
/// inside the bin and the frame nearest the centre gives the cell alone (the first of equals).
std::optional<HdrMerge> mergeHdrBin(const std::vector<FrameSample>& samples,
                                    std::vector<double> offCentreDeg = {});

}  // namespace slicecap::capture
