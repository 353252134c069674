// A sphere of the material lit by a distant point light: to judge a table at a glance.
#pragma once

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/render/canvas.hpp"

namespace slicecap::render {

/// \brief A sphere of diameter `size` pixels seen straight from above (orthographic, the viewer
/// on the +z axis), covered by the material with its tangent (azimuth 0) along the picture's x
/// axis projected onto the surface, lit by a distant point light toward `light` (theta from the
/// viewing axis, phi counter-clockwise from the picture's right). Each pixel shows f_r(l, v)
/// cos(theta_i) from the table (linear interpolation on the grid; elevations above 75 deg use the
/// 75 deg ring), divided by `whiteLevel`, clipped and sRGB-encoded; 2 x 2 samples a pixel.
/// Unlit surface is black, the background kSheetBackground. Throws RenderError for a
/// size below 8 or a whiteLevel that is not positive.
Canvas renderSphere(const Abrdf& table, const Direction& light, int size, double whiteLevel);

}  // namespace slicecap::render
