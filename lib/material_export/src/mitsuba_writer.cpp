// The fit as Mitsuba 3 XML: blendbsdf(diffuse, roughconductor) weighted so that the blend is a sum.
#include "slicecap/material_export/mitsuba_writer.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "slicecap/io/file_replacement.hpp"
#include "xml_text.hpp"

namespace slicecap::material_export {
namespace {

using detail::num;

// F0' = 1 would need an infinite eta; 0 gives eta = 1, a Fresnel of 0 at every angle where
// Schlick still rises to 1 at grazing. Both ends are kept just inside.
constexpr double kMinF0 = 1e-4, kMaxF0 = 0.999;

std::string rgbElement(const char* name, const Rgb& c) {
  return std::string("<rgb name=\"") + name + "\" value=\"" + detail::rgbText(c) + "\"/>";
}

}  // namespace

MitsubaExport mitsubaSnippet(const fit::FittedMaterial& fitted, const std::string& source) {
  const fit::FittedMaterial m = fitted.canonical();
  MitsubaExport out;
  out.report.format = "Mitsuba 3";
  auto& losses = out.report.losses;

  // Blend weight w: the blend is (1 - w) A + w B, so A = diffuse / (1 - w), B = specular / w
  // sum to the fit. w = S / (S + D) keeps both scaled reflectances at most S + D (<= 1 for any
  // material that conserves energy at normal incidence).
  const double diffuseMax = m.diffuseAlbedo.maxChannel(), specularMax = m.specularF90;
  const double total = diffuseMax + specularMax;
  const double weight = total > 0.0 ? specularMax / total : 0.0;
  Rgb diffuseReflectance, eta;
  for (std::size_t c = 0; c < 3; ++c) {
    diffuseReflectance[c] = weight < 1.0 ? m.diffuseAlbedo[c] / (1.0 - weight) : 0.0;
    const double ratio = m.specularF90 > 0.0 ? m.specularF0[c] / m.specularF90 : 0.0;
    const double f0 = std::clamp(ratio, kMinF0, kMaxF0);
    eta[c] = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
  }
  const double specularScale = weight > 0.0 ? m.specularF90 / weight : 0.0;
  if (m.specularF0.maxChannel() > m.specularF90 + 1e-9)
    losses.push_back({LossKind::SpecularColourAtGrazing,
                      "f0 " + num(m.specularF0.maxChannel()) + " exceeds f90 " + num(m.specularF90) +
                          ": the conductor's F0 is capped at its grazing value"});
  losses.push_back({LossKind::FresnelForm,
                    "roughconductor's Fresnel is the exact one of eta " + detail::rgbText(eta) +
                        " (k = 0), not Schlick's curve: equal at normal and grazing incidence"});
  losses.push_back({LossKind::ShadowingForm,
                    "Mitsuba's microfacet masking is the separable Smith G1(i) G1(o), the fit's "
                    "the height-correlated one: a little darker toward grazing"});
  losses.push_back({LossKind::TangentFromMesh,
                    "Mitsuba has no anisotropy rotation: alpha_u follows the shape's dp/du; the "
                    "snippet's rectangle is turned by tangent_deg " + num(m.tangentDeg) +
                        " so that its u axis is the fitted tangent"});
  if (m.model == fit::MaterialModel::GgxSheen)
    losses.push_back({LossKind::SheenDropped,
                      "Mitsuba 3 has no Charlie sheen BSDF: the fitted sheen (colour " +
                          detail::rgbText(m.sheenColour) + ") is left out"});

  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
    << "<!-- slicecap fit of " << detail::commentSafe(source) << " (docs/material-export.md).\n"
    << "     BSDF slicecap_fit = diffuse (albedo " << detail::rgbText(m.diffuseAlbedo)
    << ") + GGX (alpha_t " << num(m.alphaTangent) << " along u, alpha_b " << num(m.alphaBitangent)
    << ", f0 " << detail::rgbText(m.specularF0) << ", f90 " << num(m.specularF90) << "),\n"
    << "     as blendbsdf weight w with each part divided by its weight. Use it with\n"
    << "     <ref id=\"slicecap_fit\"/>; its anisotropy follows each shape's dp/du. -->\n"
    << "<scene version=\"3.0.0\">\n"
    << "  <bsdf type=\"blendbsdf\" id=\"slicecap_fit\">\n"
    << "    <float name=\"weight\" value=\"" << num(weight) << "\"/>\n"
    << "    <bsdf type=\"diffuse\">\n"
    << "      " << rgbElement("reflectance", diffuseReflectance) << "\n"
    << "    </bsdf>\n"
    << "    <bsdf type=\"roughconductor\">\n"
    << "      <string name=\"distribution\" value=\"ggx\"/>\n"
    << "      <float name=\"alpha_u\" value=\"" << num(m.alphaTangent) << "\"/>\n"
    << "      <float name=\"alpha_v\" value=\"" << num(m.alphaBitangent) << "\"/>\n"
    << "      " << rgbElement("eta", eta) << "\n"
    << "      " << rgbElement("k", Rgb::gray(0.0)) << "\n"
    << "      " << rgbElement("specular_reflectance", Rgb::gray(specularScale)) << "\n"
    << "    </bsdf>\n"
    << "  </bsdf>\n"
    << "  <!-- A flat sample, normal +z, its u axis turned onto the fitted tangent. -->\n"
    << "  <shape type=\"rectangle\" id=\"slicecap_sample\">\n"
    << "    <transform name=\"to_world\">\n"
    << "      <rotate z=\"1\" angle=\"" << num(m.tangentDeg) << "\"/>\n"
    << "    </transform>\n"
    << "    <ref id=\"slicecap_fit\"/>\n"
    << "  </shape>\n"
    << "</scene>\n";
  out.text = x.str();
  return out;
}

ExportReport writeMitsuba(const std::filesystem::path& path, const fit::FittedMaterial& material,
                          const std::string& source) {
  const MitsubaExport e = mitsubaSnippet(material, source);
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << e.text; });
  return e.report;
}

}  // namespace slicecap::material_export
