// What a format cannot say about a fitted material: every exporter returns these, typed, so that the
// CLI prints them and a test can assert on them (docs/material-export.md).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slicecap/eval/metrics.hpp"

namespace slicecap::material_export {

/// \brief The kinds of loss a conversion can have. Each names one thing the target format cannot
/// express, not a failure: the file is still written.
enum class LossKind {
  RoughnessClamped,        ///< an alpha above what the format's roughness/anisotropy reaches
  AnisotropyClamped,       ///< a ratio of alphas beyond the format's anisotropy range
  SpecularColourAtGrazing, ///< coloured F0 (or f0 > f90) the format's Fresnel cannot hold
  FresnelForm,             ///< the format's Fresnel is not Schlick with f0/f90 (a real dielectric or conductor)
  DiffuseLayering,         ///< the format dims the diffuse by the specular's reflectance; the fit does not
  SheenForm,               ///< the format's sheen is not the fitted Charlie lobe (or dims the base)
  SheenDropped,            ///< the format (as exported) has no sheen: the fitted sheen is left out
  ShadowingForm,           ///< the format's masking-shadowing is not height-correlated Smith
  TangentFromMesh,         ///< the format has no rotation: the tangent comes from the mesh's frame
  CoatForm,                ///< the format's coat is not glTF's (its Fresnel, lobe or layering)
};

/// \brief The kind's spelling in messages and JSON, e.g. "roughness-clamped".
std::string_view toString(LossKind kind);

/// \brief One loss: what is lost and by how much, in words with the numbers.
struct ConversionLoss {
  LossKind kind;
  std::string detail;
};

/// \brief What an exporter wrote and what it could not express.
struct ExportReport {
  std::string format;  ///< "glTF 2.0", "MaterialX (OpenPBR + standard_surface)", "Mitsuba 3"
  std::vector<ConversionLoss> losses;
  /// \brief The exported material's BRDF tabulated against the fitted one (slicecap compare's
  /// metrics, the fit as reference), where slicecap evaluates the format's BRDF: glTF only.
  std::optional<eval::Metrics> measured;
};

}  // namespace slicecap::material_export
