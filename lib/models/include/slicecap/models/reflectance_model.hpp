// Analytic reflectance models (ground truth for tests, the main job and the virtual rig).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::models {

/// \brief A BRDF f_r(light, view) in 1/sr, linear RGB, in the local frame of the material (z =
/// normal, x = the azimuth-0 axis of the Bonn grid).
class ReflectanceModel {
 public:
  virtual ~ReflectanceModel() = default;
  /// \brief f_r for unit vectors toward the light and the viewer, both with z > 0.
  virtual Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const = 0;
  /// \brief A one-line description with every parameter, e.g. for EXR headers and reports.
  virtual std::string describe() const = 0;
  /// \brief True if the model depends on azimuths only through phi_v - phi_i.
  virtual bool isIsotropic() const = 0;
};

/// \brief Lambertian: albedo / pi.
std::unique_ptr<ReflectanceModel> makeLambert(const Rgb& albedo);

/// \brief Anisotropic Ward (1992), normalised form: diffuse / pi + specular * exp(-tan^2 theta_h
/// (cos^2 phi_h / ax^2 + sin^2 phi_h / ay^2)) / (4 pi ax ay sqrt(cos_i cos_v)); phi_h measured from
/// the tangent, which lies at azimuth `tangentDeg`.
std::unique_ptr<ReflectanceModel> makeWard(const Rgb& diffuse, const Rgb& specular, double alphaX,
                                           double alphaY, double tangentDeg = 0.0);

/// \brief Anisotropic GGX microfacet model with height-correlated Smith masking and Schlick Fresnel
/// (normal-incidence reflectance f0), plus a Lambertian base.
std::unique_ptr<ReflectanceModel> makeAnisotropicGgx(const Rgb& diffuse, const Rgb& f0,
                                                     double alphaX, double alphaY,
                                                     double tangentDeg = 0.0);

/// \brief Normalised Blinn-Phong: diffuse / pi + specular (n + 2) / (8 pi) cos^n theta_h.
std::unique_ptr<ReflectanceModel> makeBlinnPhong(const Rgb& diffuse, const Rgb& specular,
                                                 double exponent);

/// \brief The elevation-only lobe Method B assumes: k (cos theta_i cos theta_v)^n, k per channel.
std::unique_ptr<ReflectanceModel> makeElevationLobe(const Rgb& k, double exponent);

/// \brief Velvet-like sheen (the "Charlie" distribution of Estevez and Kulla, 2017) over a
/// Lambertian base: strong at grazing angles, dark at normal incidence.
std::unique_ptr<ReflectanceModel> makeSheen(const Rgb& diffuse, const Rgb& sheen, double roughness);

/// \brief The table of a model on the Bonn grid: A[l][v] = f_r(direction l, direction v).
Abrdf tabulate(const ReflectanceModel& model);

/// \brief A named material with realistic parameters.
struct NamedMaterial {
  std::string name;
  std::shared_ptr<const ReflectanceModel> model;
};

/// \brief The built-in anisotropic materials (brushed metals, satins, a velvet-like sheen, rotated
/// Ward and GGX lobes); used by the main job, the evaluation and tests.
std::vector<NamedMaterial> anisotropicMaterials();
/// \brief The built-in isotropic materials (matte paint, plastics, Blinn-Phong, sheen).
std::vector<NamedMaterial> isotropicMaterials();
/// \brief The model of a built-in name, or nullptr.
std::shared_ptr<const ReflectanceModel> findMaterial(const std::string& name);

}  // namespace slicecap::models
