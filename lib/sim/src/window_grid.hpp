// The per-pixel lookup of the window's radiance in an exposure pose's BRDF grid (renderer.cpp's
// inner loop; inline so that it stays in that loop).
#pragma once

#include <algorithm>
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
};

// Adds the window's radiance at plane point (x, y), weighted by the raster's window coverage.
inline void addWindowRadiance(const WindowGrid& g, float x, float y, float coverage, float* out) {
  const int nodes = g.nodes;
  const float gx = std::clamp((x - g.x0Mm) / g.nodeStepX, 0.0f, g.maxNode);
  const float gy = std::clamp((y - g.y0Mm) / g.nodeStepY, 0.0f, g.maxNode);
  const int gi = static_cast<int>(gx), gj = static_cast<int>(gy);
  const float ex = gx - gi, ey = gy - gj;
  const float* g00 = &g.radiance[3 * (std::size_t(gj) * nodes + gi)];
  const float* g01 = g00 + 3 * nodes;
  // A patterned material: the pixel's mix of the two components' radiance.
  const std::size_t second = std::size_t(nodes) * nodes * 3;
  const float first = g.pattern ? static_cast<float>(g.pattern->firstWeightAt(x, y)) : 1.0f;
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
