// Sphere and cylinder generation with analytic normals and tangents (no tangent-space generator is
// needed: each surface's parametrisation gives its tangent directly).
#include "slicecap/material_export/preview_mesh.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "slicecap/material_export/material_export_error.hpp"

namespace slicecap::material_export {
namespace {

using Vec3 = std::array<float, 3>;

void addVertex(PreviewMesh& mesh, Vec3 p, Vec3 n, Vec3 t, float u, float v) {
  mesh.positions.push_back(p);
  mesh.normals.push_back(n);
  mesh.tangents.push_back({t[0], t[1], t[2], 1.0f});
  mesh.uvs.push_back({u, v});
}

// Triangles of a (columns+1) x (rows+1) vertex grid starting at `first`, row-major.
void addGrid(PreviewMesh& mesh, std::uint32_t first, int columns, int rows, bool flip) {
  const auto at = [&](int column, int row) {
    return first + static_cast<std::uint32_t>(row * (columns + 1) + column);
  };
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      const std::uint32_t a = at(column, row), b = at(column + 1, row), c = at(column + 1, row + 1),
                          d = at(column, row + 1);
      if (flip) {
        mesh.indices.insert(mesh.indices.end(), {a, c, b, a, d, c});
      } else {
        mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
      }
    }
  }
}

}  // namespace

PreviewMesh uvSphere(double radius, int segments, int rings) {
  if (!(radius > 0.0) || segments < 3 || rings < 2)
    throw MaterialExportError("uvSphere: needs radius > 0, segments >= 3, rings >= 2");
  PreviewMesh mesh;
  mesh.name = "sphere";
  const double pi = std::numbers::pi;
  // Rows from the +y pole (v = 0, glTF's top of the texture) down to the -y pole.
  for (int row = 0; row <= rings; ++row) {
    const double theta = pi * row / rings;
    for (int column = 0; column <= segments; ++column) {
      const double phi = 2.0 * pi * column / segments;
      // Longitude phi = 0 faces +z (a glTF viewer's default camera looks down -z).
      const Vec3 n{static_cast<float>(std::sin(theta) * std::sin(phi)),
                   static_cast<float>(std::cos(theta)),
                   static_cast<float>(std::sin(theta) * std::cos(phi))};
      const Vec3 p{static_cast<float>(radius * n[0]), static_cast<float>(radius * n[1]),
                   static_cast<float>(radius * n[2])};
      // d position / d phi, normalised: defined at the poles too (it does not depend on theta).
      const Vec3 t{static_cast<float>(std::cos(phi)), 0.0f, static_cast<float>(-std::sin(phi))};
      addVertex(mesh, p, n, t, static_cast<float>(column) / segments,
                static_cast<float>(row) / rings);
    }
  }
  // Seen from outside, increasing column goes right (east) and increasing row goes down.
  addGrid(mesh, 0, segments, rings, true);
  return mesh;
}

PreviewMesh cylinder(double radius, double height, int segments) {
  if (!(radius > 0.0) || !(height > 0.0) || segments < 3)
    throw MaterialExportError("cylinder: needs radius > 0, height > 0, segments >= 3");
  PreviewMesh mesh;
  mesh.name = "cylinder";
  const double pi = std::numbers::pi;
  const float top = static_cast<float>(height / 2.0), r = static_cast<float>(radius);
  // Side: rows top (v = 0) to bottom.
  for (int row = 0; row <= 1; ++row) {
    for (int column = 0; column <= segments; ++column) {
      const double phi = 2.0 * pi * column / segments;
      const float s = static_cast<float>(std::sin(phi)), c = static_cast<float>(std::cos(phi));
      addVertex(mesh, {r * s, row == 0 ? top : -top, r * c}, {s, 0.0f, c}, {c, 0.0f, -s},
                static_cast<float>(column) / segments, static_cast<float>(row));
    }
  }
  addGrid(mesh, 0, segments, 1, true);
  // Caps: a fan around a centre vertex, tangent +x; the bitangent cross(n, x) is -z on top.
  for (const float side : {1.0f, -1.0f}) {
    const auto centre = static_cast<std::uint32_t>(mesh.positions.size());
    addVertex(mesh, {0.0f, side * top, 0.0f}, {0.0f, side, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.5f, 0.5f);
    for (int column = 0; column <= segments; ++column) {
      const double phi = 2.0 * pi * column / segments;
      const float s = static_cast<float>(std::sin(phi)), c = static_cast<float>(std::cos(phi));
      addVertex(mesh, {r * s, side * top, r * c}, {0.0f, side, 0.0f}, {1.0f, 0.0f, 0.0f},
                0.5f + 0.5f * s, 0.5f - 0.5f * side * c);
    }
    for (int column = 0; column < segments; ++column) {
      const std::uint32_t a = centre + 1 + static_cast<std::uint32_t>(column);
      // Counter-clockwise seen from outside: seen from +y the ring runs counter-clockwise with phi.
      if (side > 0) {
        mesh.indices.insert(mesh.indices.end(), {centre, a, a + 1});
      } else {
        mesh.indices.insert(mesh.indices.end(), {centre, a + 1, a});
      }
    }
  }
  return mesh;
}

}  // namespace slicecap::material_export
