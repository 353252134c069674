// The fit as MaterialX 1.39 nodes: open_pbr_surface + standard_surface, each in a surfacematerial.
#include "slicecap/material_export/mtlx_writer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <sstream>

#include "slicecap/io/file_replacement.hpp"
#include "slicecap/material_export/gltf_material.hpp"
#include "xml_text.hpp"

namespace slicecap::material_export {
namespace {

using detail::num;
using detail::rgbText;

// The largest anisotropy MaterialX's mx_roughness_anisotropy honours (it clamps to 0.98).
constexpr double kMaxStandardSurfaceAnisotropy = 0.98;

std::string input(const char* name, const char* type, const std::string& value) {
  return std::string("    <input name=\"") + name + "\" type=\"" + type + "\" value=\"" + value +
         "\" />\n";
}

using Losses = std::vector<ConversionLoss>;

// The shading parameters both surfaces are written from.
struct MtlxParameters {
  GltfMaterial gltf;  // colours, IOR and sheen as the glTF export maps them
  Rgb specularColour;
  double openPbrRoughness = 0.0, openPbrAnisotropy = 0.0;
  double standardRoughness = 0.0, standardAnisotropy = 0.0;
  bool sheen = false;
  bool coat = false;
  double coatRoughness = 0.0;  // sqrt(coat alpha), capped at 1
  // OpenPBR's base inputs under its coat, chosen so that what OpenPBR derives from them under the
  // coat is the fit's base (mapCoat); without a coat, specular_ior and openPbrRoughness.
  double openPbrSpecularIor = 1.5, openPbrBaseRoughness = 0.0;
};

// The coat's IOR, glTF KHR_materials_clearcoat's fixed one.
constexpr double kCoatIor = 1.5;

// Colours: the same F0 split as the glTF export (IOR from the brightest channel of f0 / f90),
// but OpenPBR and standard_surface tint the whole dielectric Fresnel with specular_color, so
// specular_color = f90 x the glTF colour: exact at normal incidence.
void mapColours(const fit::FittedMaterial& m, MtlxParameters& p, Losses& losses) {
  const GltfConversion gltf = toGltfMaterial(m);
  p.gltf = gltf.material;
  const GltfMaterial& g = p.gltf;
  for (std::size_t c = 0; c < 3; ++c) p.specularColour[c] = g.specularFactor * g.specularColorFactor[c];
  losses.push_back({LossKind::FresnelForm,
                    "OpenPBR and standard_surface use the exact dielectric Fresnel of specular_ior " +
                        num(g.ior) + " times specular_color, not Schlick's f0/f90 curve"});
  if (p.specularColour.maxChannel() - p.specularColour.minChannel() > 1e-3 ||
      std::abs(p.specularColour.maxChannel() - m.specularF90) > 1e-3)
    losses.push_back({LossKind::SpecularColourAtGrazing,
                      "specular_color " + rgbText(p.specularColour) +
                          " also scales the grazing reflectance, where the fit has a grey f90 " +
                          num(m.specularF90)});
  for (const ConversionLoss& loss : gltf.losses)
    if (loss.kind == LossKind::DiffuseLayering || loss.kind == LossKind::SpecularColourAtGrazing)
      losses.push_back({loss.kind, "as in glTF: " + loss.detail});
}

// The lobe in both surfaces' terms, and the sheen's loss.
void mapLobe(const fit::FittedMaterial& m, MtlxParameters& p, Losses& losses) {
  // OpenPBR roughness and anisotropy (NG_open_pbr_anisotropy inverted).
  const double ratio = m.alphaBitangent / m.alphaTangent;  // <= 1 in the canonical form
  p.openPbrAnisotropy = 1.0 - ratio;
  p.openPbrRoughness = std::sqrt(m.alphaTangent / std::sqrt(2.0 / (1.0 + ratio * ratio)));
  if (p.openPbrRoughness > 1.0) {
    losses.push_back({LossKind::RoughnessClamped,
                      "OpenPBR specular_roughness " + num(p.openPbrRoughness) + " capped at 1"});
    p.openPbrRoughness = 1.0;
  }
  // standard_surface: alpha_x alpha_y = r^4, alpha_y / alpha_x = 1 - a.
  p.standardAnisotropy = 1.0 - ratio;
  if (p.standardAnisotropy > kMaxStandardSurfaceAnisotropy) {
    losses.push_back({LossKind::AnisotropyClamped,
                      "standard_surface specular_anisotropy " + num(p.standardAnisotropy) +
                          " > 0.98, where MaterialX clamps it: alpha ratio " + num(ratio) +
                          " becomes 0.02"});
    p.standardAnisotropy = kMaxStandardSurfaceAnisotropy;
  }
  p.standardRoughness = std::pow(m.alphaTangent * m.alphaBitangent, 0.25);
  if (m.alphaTangent > 1.0)
    losses.push_back({LossKind::RoughnessClamped,
                      "standard_surface caps alpha along the tangent at 1 (fit: " +
                          num(m.alphaTangent) + ")"});

  p.sheen = fit::hasSheen(m.model);
  if (p.sheen)
    losses.push_back({LossKind::SheenForm,
                      "OpenPBR's fuzz (and standard_surface's sheen) layer over the base and dim it "
                      "by their albedo; OpenPBR's fuzz lobe is not the fitted Charlie lobe"});
}

// OpenPBR's base under a coat of weight c (the OpenPBR specification's specular IOR ratio with its
// total-internal-reflection fix, as MaterialX's open_pbr_surface graph computes it): the base
// reflects with eta_s = mix(n, n > 1.5 ? n / 1.5 : 1.5 / n, c), not n. Returns the n for which
// eta_s is `target`: n = target / (1 - c / 3) when that is at least 1.5, else a root of
// (1 - c) n^2 - target n + 1.5 c = 0 in [1, 1.5]; when there is none (a base reflecting less than
// the coat leaves possible), the n of the smallest eta_s, and `exact` false.
double specularIorUnderCoat(double target, double c, bool& exact) {
  exact = true;
  if (c <= 0.0) return target;
  const double above = target / (1.0 - c / 3.0);
  if (above >= kCoatIor) return above;
  const double disc = target * target - 4.0 * (1.0 - c) * kCoatIor * c;
  if (disc >= 0.0) {
    for (const double sign : {1.0, -1.0}) {
      const double n = (target + sign * std::sqrt(disc)) / (2.0 * (1.0 - c));
      if (n >= 1.0 && n <= kCoatIor) return n;
    }
  }
  exact = false;
  return std::clamp(std::sqrt(kCoatIor * c / (1.0 - c)), 1.0, kCoatIor);
}

// OpenPBR's base roughness under a coat of roughness rc and weight c (the specification's coat
// roughening, as MaterialX's graph): r' = mix(r, (r^4 + 2 rc^4)^(1/4), c). Returns the r whose r'
// is `target` (bisection: r' grows with r), 0 and `exact` false when even r = 0 is rougher.
double baseRoughnessUnderCoat(double target, double rc, double c, bool& exact) {
  const auto roughened = [&](double r) {
    return (1.0 - c) * r + c * std::pow(std::pow(r, 4) + 2.0 * std::pow(rc, 4), 0.25);
  };
  exact = roughened(0.0) <= target;
  if (!exact) return 0.0;
  double low = 0.0, high = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    (roughened(mid) < target ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// The coat: both surfaces have one of IOR 1.5 with roughness = sqrt(alpha), as the fit's
// (glTF's) coat, but layered their own way. OpenPBR also changes the base under its coat (its IOR
// relative to the coat, its roughness widened by the coat's): its base inputs are inverted so that
// the base it derives is the fit's.
void mapCoat(const fit::FittedMaterial& m, MtlxParameters& p, Losses& losses) {
  p.openPbrSpecularIor = p.gltf.ior;
  p.openPbrBaseRoughness = p.openPbrRoughness;
  p.coat = fit::hasCoat(m.model);
  if (!p.coat) return;
  p.coatRoughness = std::sqrt(m.coatAlpha);
  if (p.coatRoughness > 1.0) {
    losses.push_back({LossKind::RoughnessClamped,
                      "coat_roughness " + num(p.coatRoughness) + " capped at 1"});
    p.coatRoughness = 1.0;
  }
  losses.push_back({LossKind::CoatForm,
                    "OpenPBR's and standard_surface's coat use the exact dielectric Fresnel of "
                    "IOR 1.5 at each microfacet and dim the base by the coat's albedo; the fit "
                    "(glTF's layering) takes Schlick's 0.04 at the view's angle to the normal"});
  bool iorExact = true, roughnessExact = true;
  p.openPbrSpecularIor = specularIorUnderCoat(p.gltf.ior, m.coatWeight, iorExact);
  p.openPbrBaseRoughness =
      baseRoughnessUnderCoat(p.openPbrRoughness, p.coatRoughness, m.coatWeight, roughnessExact);
  // Without a specular (specular_color 0) the base's IOR shows nowhere.
  if (!iorExact && p.specularColour.maxChannel() > 0.0)
    losses.push_back({LossKind::CoatForm,
                      "OpenPBR sets the base's IOR relative to its coat: under coat_weight " +
                          num(m.coatWeight) + " no specular_ior gives the fit's base F0 (IOR " +
                          num(p.gltf.ior) + "); specular_ior " + num(p.openPbrSpecularIor) +
                          " comes nearest"});
  if (!roughnessExact)
    losses.push_back({LossKind::CoatForm,
                      "OpenPBR widens the base's lobe under its coat beyond the fit's (base "
                      "roughness " + num(p.openPbrRoughness) + "): specular_roughness 0"});
}

// The comment, and the tangent both surfaces share: cos(a) T + sin(a) B from the surface's own
// tangent T and bitangent B, a = tangent_deg, normalised. Not rotate3d: the node is specified as a
// counter-clockwise turn, but MaterialX's own GLSL, OSL and MDL code for it (1.39.5) turn the other
// way (AcademySoftwareFoundation/MaterialX#2083), so a renderer built on them would put the lobe at
// -tangent_deg. Products and a sum mean the same in every implementation.
void writeHeaderAndTangent(std::ostream& x, const fit::FittedMaterial& m, const std::string& source) {
  const double a = m.tangentDeg * std::numbers::pi / 180.0;
  x << "<?xml version=\"1.0\"?>\n"
    << "<!-- slicecap fit of " << detail::commentSafe(source) << " (docs/material-export.md).\n"
    << "     Primary material: slicecap_fit (OpenPBR Surface); alternative:\n"
    << "     slicecap_fit_standard_surface. The fitted tangent is cos(a) T + sin(a) B, normalised:\n"
    << "     the surface tangent T (the table's azimuth-0 axis on the mesh) turned by a = "
    << num(m.tangentDeg) << " deg\n"
    << "     toward the bitangent B. Fit: alpha_t " << num(m.alphaTangent) << ", alpha_b "
    << num(m.alphaBitangent) << ". -->\n"
    << "<materialx version=\"1.39\" colorspace=\"lin_rec709\">\n"
    << "  <tangent name=\"surface_tangent\" type=\"vector3\">\n"
    << input("space", "string", "world") << "  </tangent>\n"
    << "  <bitangent name=\"surface_bitangent\" type=\"vector3\">\n"
    << input("space", "string", "world") << "  </bitangent>\n"
    << "  <multiply name=\"tangent_share\" type=\"vector3\">\n"
    << "    <input name=\"in1\" type=\"vector3\" nodename=\"surface_tangent\" />\n"
    << input("in2", "float", num(std::cos(a))) << "  </multiply>\n"
    << "  <multiply name=\"bitangent_share\" type=\"vector3\">\n"
    << "    <input name=\"in1\" type=\"vector3\" nodename=\"surface_bitangent\" />\n"
    << input("in2", "float", num(std::sin(a))) << "  </multiply>\n"
    << "  <add name=\"turned_tangent\" type=\"vector3\">\n"
    << "    <input name=\"in1\" type=\"vector3\" nodename=\"tangent_share\" />\n"
    << "    <input name=\"in2\" type=\"vector3\" nodename=\"bitangent_share\" />\n"
    << "  </add>\n"
    << "  <normalize name=\"fitted_tangent\" type=\"vector3\">\n"
    << "    <input name=\"in\" type=\"vector3\" nodename=\"turned_tangent\" />\n"
    << "  </normalize>\n";
}

void writeOpenPbrMaterial(std::ostream& x, const fit::FittedMaterial& m, const MtlxParameters& p) {
  const GltfMaterial& g = p.gltf;
  x << "  <open_pbr_surface name=\"slicecap_fit_open_pbr\" type=\"surfaceshader\">\n"
    << input("base_weight", "float", "1") << input("base_color", "color3", rgbText(g.baseColorFactor))
    << input("base_metalness", "float", "0") << input("specular_weight", "float", "1")
    << input("specular_color", "color3", rgbText(p.specularColour))
    << input("specular_roughness", "float", num(p.openPbrBaseRoughness))
    << input("specular_ior", "float", num(p.openPbrSpecularIor))
    << input("specular_roughness_anisotropy", "float", num(p.openPbrAnisotropy));
  if (p.sheen)
    x << input("fuzz_weight", "float", "1")
      << input("fuzz_color", "color3", rgbText(g.sheenColorFactor))
      << input("fuzz_roughness", "float", num(m.sheenRoughness));
  // coat_darkening 0: glTF's coat has no darkening of the base by internal reflections.
  if (p.coat)
    x << input("coat_weight", "float", num(m.coatWeight))
      << input("coat_roughness", "float", num(p.coatRoughness))
      << input("coat_ior", "float", "1.5") << input("coat_darkening", "float", "0");
  x << "    <input name=\"geometry_tangent\" type=\"vector3\" nodename=\"fitted_tangent\" />\n"
    << "  </open_pbr_surface>\n"
    << "  <surfacematerial name=\"slicecap_fit\" type=\"material\">\n"
    << "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"slicecap_fit_open_pbr\" />\n"
    << "  </surfacematerial>\n";
}

void writeStandardSurfaceMaterial(std::ostream& x, const fit::FittedMaterial& m,
                                  const MtlxParameters& p) {
  const GltfMaterial& g = p.gltf;
  x << "  <standard_surface name=\"slicecap_fit_standard_surface_shader\" type=\"surfaceshader\">\n"
    << input("base", "float", "1") << input("base_color", "color3", rgbText(g.baseColorFactor))
    << input("specular", "float", "1") << input("specular_color", "color3", rgbText(p.specularColour))
    << input("specular_roughness", "float", num(p.standardRoughness))
    << input("specular_IOR", "float", num(g.ior))
    << input("specular_anisotropy", "float", num(p.standardAnisotropy))
    // specular_rotation stays 0: its graph turns the tangent with rotate3d (writeHeaderAndTangent).
    << input("specular_rotation", "float", "0");
  if (p.sheen)
    x << input("sheen", "float", "1") << input("sheen_color", "color3", rgbText(g.sheenColorFactor))
      << input("sheen_roughness", "float", num(m.sheenRoughness));
  if (p.coat)
    x << input("coat", "float", num(m.coatWeight))
      << input("coat_roughness", "float", num(p.coatRoughness)) << input("coat_IOR", "float", "1.5");
  x << "    <input name=\"tangent\" type=\"vector3\" nodename=\"fitted_tangent\" />\n"
    << "  </standard_surface>\n"
    << "  <surfacematerial name=\"slicecap_fit_standard_surface\" type=\"material\">\n"
    << "    <input name=\"surfaceshader\" type=\"surfaceshader\" "
       "nodename=\"slicecap_fit_standard_surface_shader\" />\n"
    << "  </surfacematerial>\n";
}

}  // namespace

MtlxExport mtlxDocument(const fit::FittedMaterial& fitted, const std::string& source) {
  const fit::FittedMaterial m = fitted.canonical();
  MtlxExport out;
  out.report.format = "MaterialX (OpenPBR Surface + standard_surface)";
  MtlxParameters p;
  mapColours(m, p, out.report.losses);
  mapLobe(m, p, out.report.losses);
  mapCoat(m, p, out.report.losses);
  std::ostringstream x;
  writeHeaderAndTangent(x, m, source);
  writeOpenPbrMaterial(x, m, p);
  writeStandardSurfaceMaterial(x, m, p);
  x << "</materialx>\n";
  out.text = x.str();
  return out;
}

ExportReport writeMtlx(const std::filesystem::path& path, const fit::FittedMaterial& material,
                       const std::string& source) {
  const MtlxExport e = mtlxDocument(material, source);
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << e.text; });
  return e.report;
}

}  // namespace slicecap::material_export
