// The per-pixel lookup of the window's radiance in an exposure pose's BRDF grid (renderer.cpp's
// inner loop; inline so that it stays in that loop).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "slicecap/sim/patterned_material.hpp"

namespace slicecap::sim {

// One exposure pose's window radiance at the BRDF grid's nodes (FrameRenderer::PoseState's grid),
// with what the per-pixel lookup needs to find a point's cell.
struct WindowGrid {
  const float* radiance;
  int nodes;
  float nodeStepX, nodeStepY;
  float x0Mm, y0Mm;
  float maxNode;
  const PatternedMaterial* pattern;
  // For a pattern: normalised image coordinates -> plane (the pose's imageToPlane, row by row)
  // and a pixel's size in normalised image coordinates (1 / the focal lengths; the distortion's
  // local change of scale, a few percent at the edges, left out), which give each pixel's
  // footprint on the plane.
  float h[9];
  float pixelXn, pixelYn;
};

// The half-widths (mm) of the plane box that pixel (xn, yn), at plane point (x, y), covers: the
// homography's Jacobian there times a pixel's size, each plane axis spanning what both image
// axes move it (the bounding box of the pixel's parallelogram).
inline void pixelFootprint(const WindowGrid& g, float xn, float yn, float x, float y, float& halfX,
                           float& halfY) {
  const float* h = g.h;
  const float invW = 1.0f / (h[6] * xn + h[7] * yn + h[8]);
  const float dxdu = (h[0] - x * h[6]) * invW, dxdv = (h[1] - x * h[7]) * invW;
  const float dydu = (h[3] - y * h[6]) * invW, dydv = (h[4] - y * h[7]) * invW;
  halfX = 0.5f * (std::abs(dxdu) * g.pixelXn + std::abs(dxdv) * g.pixelYn);
  halfY = 0.5f * (std::abs(dydu) * g.pixelXn + std::abs(dydv) * g.pixelYn);
}

// Adds the window's radiance at plane point (x, y) of pixel (xn, yn) (normalised image
// coordinates), weighted by the raster's window coverage; a pattern as the pixel's area reads it.
inline void addWindowRadiance(const WindowGrid& g, float x, float y, float xn, float yn,
                              float coverage, float* out) {
  const int nodes = g.nodes;
  const float gx = std::clamp((x - g.x0Mm) / g.nodeStepX, 0.0f, g.maxNode);
  const float gy = std::clamp((y - g.y0Mm) / g.nodeStepY, 0.0f, g.maxNode);
  const int gi = static_cast<int>(gx), gj = static_cast<int>(gy);
  const float ex = gx - gi, ey = gy - gj;
  const float* g00 = &g.radiance[3 * (std::size_t(gj) * nodes + gi)];
  const float* g01 = g00 + 3 * nodes;
  // A patterned material: the pixel's mix of the two components' radiance.
  const std::size_t second = std::size_t(nodes) * nodes * 3;
  float first = 1.0f;
  if (g.pattern) {
    float halfX = 0.0f, halfY = 0.0f;
    pixelFootprint(g, xn, yn, x, y, halfX, halfY);
    first = static_cast<float>(g.pattern->firstWeightOver(x, y, halfX, halfY));
  }
  for (int c = 0; c < 3; ++c) {
    float radiance = (1 - ey) * ((1 - ex) * g00[c] + ex * g00[c + 3]) +
                     ey * ((1 - ex) * g01[c] + ex * g01[c + 3]);
    if (g.pattern) {
      const float* k00 = g00 + second;
      const float* k01 = g01 + second;
      radiance =
          first * radiance + (1 - first) * ((1 - ey) * ((1 - ex) * k00[c] + ex * k00[c + 3]) +
                                            ey * ((1 - ex) * k01[c] + ex * k01[c + 3]));
    }
    out[c] += coverage * radiance;
  }
}

}  // namespace slicecap::sim
