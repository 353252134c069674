// Small meshes to show a material on, with the tangents an anisotropic material needs.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace slicecap::material_export {

/// \brief An indexed triangle mesh in glTF's frame (y up, metres), every vertex with a unit normal,
/// a unit tangent with handedness w = +1 (bitangent = cross(normal, tangent)) and a UV whose u grows
/// along the tangent.
struct PreviewMesh {
  std::string name;
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 3>> normals;
  std::vector<std::array<float, 4>> tangents;
  std::vector<std::array<float, 2>> uvs;
  std::vector<std::uint32_t> indices;  ///< counter-clockwise triangles seen from outside
};

/// \brief A UV sphere of `radius` centred on the origin: tangent along the parallels (increasing
/// longitude, eastward), bitangent toward the +y pole, so the fitted tangent angle turns from east
/// toward north. Throws MaterialExportError when radius <= 0, segments < 3 or rings < 2.
PreviewMesh uvSphere(double radius, int segments, int rings);

/// \brief A closed cylinder along y (a brushed rod): on the side, tangent around the circumference
/// and bitangent along +y; on the caps, tangent +x. Throws MaterialExportError when radius or
/// height <= 0 or segments < 3.
PreviewMesh cylinder(double radius, double height, int segments);

}  // namespace slicecap::material_export
