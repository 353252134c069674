// Orthographic sphere shading from a tabulated BRDF.
#include "slicecap/render/sphere_render.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slicecap/core/grid_interpolation.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/render/render_error.hpp"

namespace slicecap::render {
namespace {

struct Vec3 {
  double x, y, z;
};
double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
Vec3 normalised(const Vec3& v) {
  const double length = std::sqrt(dot(v, v));
  return {v.x / length, v.y / length, v.z / length};
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// f_r cos(theta_i) at the surface point with normal n, for the world light and view directions;
// 0 where the light is below the surface.
Rgb shade(const Abrdf& table, const Vec3& n, const Vec3& light, const Vec3& view) {
  // Tangent: the picture's x axis projected onto the surface (y axis where x is the normal).
  Vec3 axis{1.0, 0.0, 0.0};
  if (std::abs(n.x) > 0.999) axis = {0.0, 1.0, 0.0};
  const Vec3 t = normalised(
      {axis.x - n.x * dot(n, axis), axis.y - n.y * dot(n, axis), axis.z - n.z * dot(n, axis)});
  const Vec3 b = cross(n, t);
  const double cosI = dot(light, n), cosV = dot(view, n);
  if (cosI <= 0.0 || cosV <= 0.0) return {};
  const Direction l = toDirection({dot(light, t), dot(light, b), cosI});
  const Direction v = toDirection({dot(view, t), dot(view, b), cosV});
  return evaluate(table, l, v) * cosI;
}

}  // namespace

Canvas renderSphere(const Abrdf& table, const Direction& light, int size, double whiteLevel) {
  if (size < 8) throw RenderError("sphere: size must be at least 8 pixels");
  if (!(whiteLevel > 0.0)) throw RenderError("sphere: white level must be positive");
  const UnitVector lightVector = toUnitVector(light);
  const Vec3 toLight{lightVector.x, lightVector.y, lightVector.z};
  const Vec3 toViewer{0.0, 0.0, 1.0};
  Canvas canvas(size, size);
  const double radius = size / 2.0;
  for (int py = 0; py < size; ++py) {
    for (int px = 0; px < size; ++px) {
      Rgb sum;
      int covered = 0;
      for (int sy = 0; sy < 2; ++sy) {
        for (int sx = 0; sx < 2; ++sx) {
          const double x = (px + 0.25 + 0.5 * sx - radius) / radius;
          const double y = (radius - py - 0.25 - 0.5 * sy) / radius;  // picture y points down
          const double r2 = x * x + y * y;
          if (r2 >= 1.0) continue;
          ++covered;
          sum += shade(table, {x, y, std::sqrt(1.0 - r2)}, toLight, toViewer);
        }
      }
      if (covered == 0) continue;
      Colour c{};
      for (std::size_t k = 0; k < 3; ++k) {
        // Coverage blends the lit surface with the background at the rim.
        const double value = std::clamp(sum[k] / covered / whiteLevel, 0.0, 1.0);
        const double background = kSheetBackground[k] * (1.0 - covered / 4.0);
        c[k] = std::uint8_t(std::lround(
            std::min(255.0, eval::srgbEncode(value) * 255.0 * covered / 4.0 + background)));
      }
      canvas.set(px, py, c);
    }
  }
  return canvas;
}

}  // namespace slicecap::render
