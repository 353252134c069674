// The preview meshes carry what an anisotropic glTF material needs: unit normals, unit tangents
// perpendicular to them, outward counter-clockwise triangles and u growing along the tangent.
#include "slicecap/material_export/preview_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "slicecap/material_export/material_export_error.hpp"

namespace slicecap::material_export {
namespace {

using V = std::array<float, 3>;
double dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

void expectWellFormed(const PreviewMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  ASSERT_EQ(mesh.normals.size(), n);
  ASSERT_EQ(mesh.tangents.size(), n);
  ASSERT_EQ(mesh.uvs.size(), n);
  ASSERT_EQ(mesh.indices.size() % 3, 0u);
  for (std::size_t i = 0; i < n; ++i) {
    const V t{mesh.tangents[i][0], mesh.tangents[i][1], mesh.tangents[i][2]};
    EXPECT_NEAR(dot(mesh.normals[i], mesh.normals[i]), 1.0, 1e-5) << mesh.name << " vertex " << i;
    EXPECT_NEAR(dot(t, t), 1.0, 1e-5) << mesh.name << " vertex " << i;
    EXPECT_NEAR(dot(t, mesh.normals[i]), 0.0, 1e-5) << mesh.name << " vertex " << i;
    EXPECT_EQ(mesh.tangents[i][3], 1.0f);
  }
  int outward = 0, faces = 0;
  for (std::size_t f = 0; f < mesh.indices.size(); f += 3) {
    const std::uint32_t a = mesh.indices[f], b = mesh.indices[f + 1], c = mesh.indices[f + 2];
    ASSERT_LT(std::max({a, b, c}), n);
    const V face = cross(sub(mesh.positions[b], mesh.positions[a]),
                         sub(mesh.positions[c], mesh.positions[a]));
    if (dot(face, face) < 1e-14) continue;  // a sliver at a sphere's pole
    ++faces;
    const V mean{mesh.normals[a][0] + mesh.normals[b][0] + mesh.normals[c][0],
                 mesh.normals[a][1] + mesh.normals[b][1] + mesh.normals[c][1],
                 mesh.normals[a][2] + mesh.normals[b][2] + mesh.normals[c][2]};
    if (dot(face, mean) > 0.0) ++outward;
    // u grows along the tangent: over an edge, du has the sign of (dp . t).
    const V edge = sub(mesh.positions[b], mesh.positions[a]);
    const V t{mesh.tangents[a][0], mesh.tangents[a][1], mesh.tangents[a][2]};
    const double du = mesh.uvs[b][0] - mesh.uvs[a][0];
    if (std::abs(dot(edge, t)) > 1e-3 && std::abs(du) > 1e-6 && std::abs(du) < 0.5) {
      EXPECT_GT(du * dot(edge, t), 0.0) << mesh.name << " face " << f / 3;
    }
  }
  EXPECT_GT(faces, 0);
  EXPECT_EQ(outward, faces) << mesh.name << ": every triangle counter-clockwise from outside";
}

TEST(PreviewMesh, SphereIsWellFormed) { expectWellFormed(uvSphere(0.5, 16, 8)); }

TEST(PreviewMesh, CylinderIsWellFormed) { expectWellFormed(cylinder(0.4, 1.0, 16)); }

TEST(PreviewMesh, SphereFrontTangentIsEastAndBitangentUp) {
  const PreviewMesh s = uvSphere(1.0, 4, 2);
  // Row 1 (equator), column 0: longitude 0 faces +z.
  const std::size_t i = 1 * 5 + 0;
  EXPECT_NEAR(s.normals[i][2], 1.0, 1e-6);
  EXPECT_NEAR(s.tangents[i][0], 1.0, 1e-6);
  const V b = cross(s.normals[i], {s.tangents[i][0], s.tangents[i][1], s.tangents[i][2]});
  EXPECT_NEAR(b[1], 1.0, 1e-6);  // cross(normal, tangent) * w points to +y
}

TEST(PreviewMesh, BadSizesThrow) {
  EXPECT_THROW(uvSphere(0.0, 16, 8), material_export::MaterialExportError);
  EXPECT_THROW(uvSphere(1.0, 2, 8), material_export::MaterialExportError);
  EXPECT_THROW(cylinder(1.0, -1.0, 16), material_export::MaterialExportError);
}

}  // namespace
}  // namespace slicecap::material_export
