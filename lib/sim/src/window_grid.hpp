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

// The share of a pattern's first component over pixel (xn, yn), at plane point (x, y): the
// pixel's footprint is the parallelogram spanned by the homography's Jacobian there times a
// pixel's size. A pattern's box mean is exact for boxes along the target's axes, and the
// parallelogram's bounding box is up to ~3 x its area where a grazing view's long footprint lies
// diagonal to them, so the parallelogram is cut into kFootprintSplit^2 smaller ones, each read as
// its own bounding box (the excess then a thin fringe a third as wide).
inline constexpr int kFootprintSplit = 3;

inline double firstWeightOverPixel(const WindowGrid& g, float xn, float yn, float x, float y) {
  const float* h = g.h;
  const float invW = 1.0f / (h[6] * xn + h[7] * yn + h[8]);
  // The footprint's two edges on the plane: one pixel along the image's x, one along its y.
  const float ax = (h[0] - x * h[6]) * invW * g.pixelXn, ay = (h[3] - y * h[6]) * invW * g.pixelXn;
  const float bx = (h[1] - x * h[7]) * invW * g.pixelYn, by = (h[4] - y * h[7]) * invW * g.pixelYn;
  constexpr float kStep = 1.0f / kFootprintSplit;
  const double halfX = 0.5 * kStep * (std::abs(ax) + std::abs(bx));
  const double halfY = 0.5 * kStep * (std::abs(ay) + std::abs(by));
  double sum = 0.0;
  for (int i = 0; i < kFootprintSplit; ++i)
    for (int j = 0; j < kFootprintSplit; ++j) {
      const float s = (i + 0.5f) * kStep - 0.5f, t = (j + 0.5f) * kStep - 0.5f;
      sum += g.pattern->firstWeightOver(x + s * ax + t * bx, y + s * ay + t * by, halfX, halfY);
    }
  return sum / (kFootprintSplit * kFootprintSplit);
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
  const float first = g.pattern ? static_cast<float>(firstWeightOverPixel(g, xn, yn, x, y)) : 1.0f;
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
