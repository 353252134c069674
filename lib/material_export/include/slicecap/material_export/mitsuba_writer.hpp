// A Mitsuba 3 scene snippet with the nearest built-in BSDFs to the fitted material.
#pragma once

#include <filesystem>
#include <string>

#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/material_export/conversion_loss.hpp"

namespace slicecap::material_export {

/// \brief The XML text and what it loses. Never throws. The BSDF (id "slicecap_fit") is a
/// `blendbsdf` (weight w) of a `diffuse` with reflectance albedo / (1 - w) and a `roughconductor`
/// (GGX, alpha_u = alpha_t along the shading frame's u, alpha_v = alpha_b) whose Fresnel is the
/// exact one of k = 0 and eta = (1 + sqrt(F0')) / (1 - sqrt(F0')), F0' = f0 / w per channel, so the
/// blend is albedo / pi + F D G / (4 cos cos) with F = f0 at normal incidence and w at grazing.
/// Mitsuba refuses reflectances above 1, so w = f90 clamped into [max f0, 1 - max albedo]. The
/// tangent angle has no BSDF parameter in Mitsuba: the snippet's `rectangle` (id
/// "slicecap_sample") is turned by tangent_deg about its normal so that its u axis is the tangent.
struct MitsubaExport {
  std::string text;
  ExportReport report;
};
MitsubaExport mitsubaSnippet(const fit::FittedMaterial& material, const std::string& source);

/// \brief Writes mitsubaSnippet to `path` (replaced whole). Throws io::IoError naming the path.
ExportReport writeMitsuba(const std::filesystem::path& path, const fit::FittedMaterial& material,
                          const std::string& source);

}  // namespace slicecap::material_export
