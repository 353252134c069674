// The paper's Fig. 1 picture of a table: 81 x 81 entries, blocks of subspaces, light-major.
#pragma once

#include "slicecap/core/abrdf.hpp"
#include "slicecap/render/canvas.hpp"

namespace slicecap::render {

/// \brief Side in pixels of a layout picture: 81 entries of `pixelsPerEntry` plus a 1-pixel line
/// between the six elevation rings.
int layoutSide(int pixelsPerEntry);

/// \brief The table in the 81 x 81 layout: row = light direction, column = view direction, both
/// in the Bonn order, so the 36 (theta_i, theta_v) subspaces are the blocks between the ring
/// lines. Each entry shows the paper's 8-bit encoding (times cos theta_i, divided by
/// `referenceMax`, clipped, sRGB), which is exactly what the metrics compare. Throws
/// RenderError for pixelsPerEntry < 1 or a referenceMax that is not positive.
Canvas layoutImage(const Abrdf& table, double referenceMax, int pixelsPerEntry = 3);

/// \brief |reference - test| of the two 8-bit encodings, per channel, times `gain` (the paper's
/// x10 difference images), clipped to 255; same layout. Same errors as layoutImage.
Canvas differenceImage(const Abrdf& reference, const Abrdf& test, double referenceMax,
                       int gain = 10, int pixelsPerEntry = 3);

}  // namespace slicecap::render
