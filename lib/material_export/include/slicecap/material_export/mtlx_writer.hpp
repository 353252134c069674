// A MaterialX document of the fitted material: an OpenPBR Surface (the primary material) and a
// standard_surface alternative, both with the fitted tangent direction.
#pragma once

#include <filesystem>
#include <string>

#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/material_export/conversion_loss.hpp"

namespace slicecap::material_export {

/// \brief The .mtlx text and what it loses. Never throws. Conventions (docs/material-export.md):
/// - OpenPBR: alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t (MaterialX's
///   NG_open_pbr_anisotropy), so a = 1 - alpha_b / alpha_t and r = sqrt(alpha_t / sqrt(2 / (1 +
///   (alpha_b / alpha_t)^2))); geometry_tangent is normalize(cos(a) T + sin(a) B), a = tangent_deg,
///   from the surface's world tangent T and bitangent B (no rotate3d: MaterialX's generators turn
///   it the other way from its specification); OpenPBR has no rotation input.
/// - standard_surface: alpha_x = r^2 / sqrt(1 - a), alpha_y = r^2 sqrt(1 - a) (MaterialX's
///   mx_roughness_anisotropy, a <= 0.98), so r = (alpha_t alpha_b)^(1/4), a = 1 - alpha_b /
///   alpha_t; its `tangent` is the same turned tangent and specular_rotation 0.
struct MtlxExport {
  std::string text;
  ExportReport report;
};
MtlxExport mtlxDocument(const fit::FittedMaterial& material, const std::string& source);

/// \brief Writes mtlxDocument to `path` (replaced whole). Throws io::IoError naming the path.
ExportReport writeMtlx(const std::filesystem::path& path, const fit::FittedMaterial& material,
                       const std::string& source);

}  // namespace slicecap::material_export
