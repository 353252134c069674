// The spellings of the loss kinds.
#include "slicecap/material_export/conversion_loss.hpp"

namespace slicecap::material_export {

std::string_view toString(LossKind kind) {
  switch (kind) {
    case LossKind::RoughnessClamped: return "roughness-clamped";
    case LossKind::AnisotropyClamped: return "anisotropy-clamped";
    case LossKind::SpecularColourAtGrazing: return "specular-colour-at-grazing";
    case LossKind::FresnelForm: return "fresnel-form";
    case LossKind::DiffuseLayering: return "diffuse-layering";
    case LossKind::SheenForm: return "sheen-form";
    case LossKind::SheenDropped: return "sheen-dropped";
    case LossKind::ShadowingForm: return "shadowing-form";
    case LossKind::TangentFromMesh: return "tangent-from-mesh";
    case LossKind::CoatForm: return "coat-form";
  }
  return "unknown";
}

}  // namespace slicecap::material_export
