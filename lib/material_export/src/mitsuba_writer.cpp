// The fit as Mitsuba 3 XML: blendbsdf(diffuse, roughconductor) weighted so that the blend is a sum.
#include "slicecap/material_export/mitsuba_writer.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "slicecap/io/file_replacement.hpp"
#include "slicecap/material_export/mitsuba_sheen.hpp"
#include "xml_text.hpp"

namespace slicecap::material_export {
namespace {

using detail::num;

// F0' = 1 would need an infinite eta; 0 gives eta = 1, a Fresnel of 0 at every angle where
// Schlick still rises to 1 at grazing. Both ends are kept just inside.
constexpr double kMinF0 = 1e-4, kMaxF0 = 0.999;
// Below this an f0 is no specular at all (the fit's bounds reach exactly 0).
constexpr double kNegligible = 1e-6;

std::string rgbElement(const char* name, const Rgb& c) {
  return std::string("<rgb name=\"") + name + "\" value=\"" + detail::rgbText(c) + "\"/>";
}

// The blendbsdf's weight and its two parts' parameters.
struct Blend {
  double weight = 0.0;
  Rgb diffuseReflectance, eta;
  bool diffuseClamped = false;  // the diffuse needed a reflectance above 1
};

// Blend weight w: the blend is (1 - w) A + w B with A = diffuse (albedo / (1 - w)) and
// B = a conductor whose Fresnel is F0 / w at normal incidence and 1 at grazing, so the sum has the
// fit's F0 exactly and w at grazing. Mitsuba refuses reflectances above 1, so w must lie in
// [max f0, 1 - max albedo] (non-empty for a material that reflects at most all light at normal
// incidence); within it, w as close to f90 as it can be.
Blend blendOf(const fit::FittedMaterial& m) {
  const double diffuseMax = m.diffuseAlbedo.maxChannel(), f0Max = m.specularF0.maxChannel();
  const double low = f0Max, high = 1.0 - diffuseMax;
  Blend b;
  b.weight = low <= high ? std::clamp(m.specularF90, low, high) : std::min(low, 1.0);
  // A fit with no specular (a velvet: f0 ~ 1e-12, f90 = 0) is the diffuse alone.
  if (f0Max <= kNegligible) b.weight = 0.0;
  const double weight = b.weight;
  for (std::size_t c = 0; c < 3; ++c) {
    double reflectance = weight < 1.0 ? m.diffuseAlbedo[c] / (1.0 - weight) : 0.0;
    if (reflectance > 1.0) {
      // Beyond rounding, only a material brighter than 1 at normal incidence gets here.
      b.diffuseClamped = b.diffuseClamped || reflectance > 1.0 + 1e-9 || weight >= 1.0;
      reflectance = 1.0;
    }
    b.diffuseReflectance[c] = reflectance;
    // With weight 0 the conductor does not count; eta 1.5 only keeps its parameters ordinary.
    const double f0 = weight > 0.0 ? std::clamp(m.specularF0[c] / weight, kMinF0, kMaxF0) : 0.04;
    b.eta[c] = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
  }
  return b;
}

// `scale` is the share of the diffuse + GGX blend in the snippet (1 without a sheen part), so that
// the figures reported are the snippet's, not the scaled blend's.
void addLosses(const fit::FittedMaterial& m, const Blend& b, double scale,
               std::vector<ConversionLoss>& losses) {
  const double diffuseMax = m.diffuseAlbedo.maxChannel(), f0Max = m.specularF0.maxChannel();
  const double weight = scale * b.weight;
  if (b.diffuseClamped || (weight >= 1.0 && diffuseMax > 0.0))
    losses.push_back({LossKind::DiffuseLayering,
                      "f0 " + num(f0Max) + " + diffuse albedo " + num(diffuseMax) +
                          " exceed 1 at normal incidence: the diffuse is capped (reflectance 1 "
                          "after the blend weight)"});
  if (std::abs(weight - m.specularF90) > 1e-6 && f0Max > kNegligible)
    losses.push_back({LossKind::SpecularColourAtGrazing,
                      "grazing reflectance " + num(weight) + " instead of the fit's f90 " +
                          num(m.specularF90) + " (the blend weight must keep both parts' "
                          "reflectances within [0, 1])"});
  losses.push_back({LossKind::FresnelForm,
                    "roughconductor's Fresnel is the exact one of eta " + detail::rgbText(b.eta) +
                        " (k = 0), not Schlick's curve: equal at normal and grazing incidence"});
  losses.push_back({LossKind::ShadowingForm,
                    "Mitsuba's microfacet masking is the separable Smith G1(i) G1(o), the fit's "
                    "the height-correlated one: a little darker toward grazing"});
  losses.push_back({LossKind::TangentFromMesh,
                    "Mitsuba has no anisotropy rotation: alpha_u follows the shape's dp/du; the "
                    "snippet's rectangle is turned by tangent_deg " + num(m.tangentDeg) +
                        " so that its u axis is the fitted tangent"});
}

// The diffuse + GGX blendbsdf, each line indented by `indent`; `idAttribute` is empty or
// ` id="..."`.
std::string baseBsdf(const fit::FittedMaterial& m, const Blend& b, const std::string& indent,
                     const std::string& idAttribute) {
  std::ostringstream x;
  x << indent << "<bsdf type=\"blendbsdf\"" << idAttribute << ">\n"
    << indent << "  <float name=\"weight\" value=\"" << num(b.weight) << "\"/>\n"
    << indent << "  <bsdf type=\"diffuse\">\n"
    << indent << "    " << rgbElement("reflectance", b.diffuseReflectance) << "\n"
    << indent << "  </bsdf>\n"
    << indent << "  <bsdf type=\"roughconductor\">\n"
    << indent << "    <string name=\"distribution\" value=\"ggx\"/>\n"
    << indent << "    <float name=\"alpha_u\" value=\"" << num(m.alphaTangent) << "\"/>\n"
    << indent << "    <float name=\"alpha_v\" value=\"" << num(m.alphaBitangent) << "\"/>\n"
    << indent << "    " << rgbElement("eta", b.eta) << "\n"
    << indent << "    " << rgbElement("k", Rgb::gray(0.0)) << "\n"
    << indent << "  </bsdf>\n"
    << indent << "</bsdf>\n";
  return x.str();
}

std::string header(const fit::FittedMaterial& m, const std::string& source) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
    << "<!-- slicecap fit of " << detail::commentSafe(source) << " (docs/material-export.md).\n"
    << "     BSDF slicecap_fit = diffuse (albedo " << detail::rgbText(m.diffuseAlbedo)
    << ") + GGX (alpha_t " << num(m.alphaTangent) << " along u, alpha_b " << num(m.alphaBitangent)
    << ", f0 " << detail::rgbText(m.specularF0) << ", f90 " << num(m.specularF90) << "),\n"
    << "     as blendbsdf weight w = grazing reflectance, the diffuse divided by (1 - w), the\n"
    << "     conductor's F0 = f0 / w. Use it with\n"
    << "     <ref id=\"slicecap_fit\"/>; its anisotropy follows each shape's dp/du. -->\n"
    << "<scene version=\"3.0.0\">\n";
  return x.str();
}

std::string sampleShape(const fit::FittedMaterial& m) {
  std::ostringstream x;
  x << "  <!-- A flat sample, normal +z, its u axis turned onto the fitted tangent. -->\n"
    << "  <shape type=\"rectangle\" id=\"slicecap_sample\">\n"
    << "    <transform name=\"to_world\">\n"
    << "      <rotate z=\"1\" angle=\"" << num(m.tangentDeg) << "\"/>\n"
    << "    </transform>\n"
    << "    <ref id=\"slicecap_fit\"/>\n"
    << "  </shape>\n"
    << "</scene>\n";
  return x.str();
}

std::string sceneText(const fit::FittedMaterial& m, const std::string& source, const Blend& b) {
  return header(m, source) + baseBsdf(m, b, "  ", " id=\"slicecap_fit\"") + sampleShape(m);
}

// The principled BSDF standing in for the sheen and its blend weight c (docs/material-export.md):
// the snippet is (1 - c) x [the diffuse + GGX blend of the fit scaled by 1 / (1 - c)] + c x
// principled, so the principled's parameters are the approximation's divided by c. c is the
// smallest that keeps its base colour and `sheen` within [0, 1], leaving the most room for the
// rest.
struct SheenPart {
  SheenApproximation approximation;
  double weight = 0.0;
  Rgb baseColour;
  double sheen = 0.0;  // principled `sheen`, with sheen_tint 1 (the base colour's hue)
};

// Mitsuba's luminance of linear sRGB (mitsuba::luminance): principled tints the sheen by
// base_color / luminance(base_color), so `sheen` carries the luminance back.
double luminance(const Rgb& c) { return 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]; }

SheenPart sheenPartOf(const fit::FittedMaterial& m) {
  SheenPart p;
  p.approximation = approximateSheen(m.sheenRoughness);
  const double a = p.approximation.diffuseScale, s = p.approximation.sheenScale;
  p.weight = std::min(1.0, std::max(a * m.sheenColour.maxChannel(), s * luminance(m.sheenColour)));
  if (p.weight <= kNegligible) return p;
  for (std::size_t c = 0; c < 3; ++c) p.baseColour[c] = m.sheenColour[c] * a / p.weight;
  p.sheen = s * luminance(m.sheenColour) / p.weight;
  return p;
}

fit::FittedMaterial scaledBy(fit::FittedMaterial m, double factor) {
  for (std::size_t c = 0; c < 3; ++c) {
    m.diffuseAlbedo[c] /= factor;
    m.specularF0[c] /= factor;
  }
  m.specularF90 /= factor;
  return m;
}

void addSheenLoss(const fit::FittedMaterial& m, const SheenPart& p,
                  std::vector<ConversionLoss>& losses) {
  const SheenApproximation& a = p.approximation;
  losses.push_back(
      {LossKind::SheenForm,
       "Mitsuba 3 has no Charlie sheen BSDF: a principled BSDF (blend weight " + num(p.weight) +
           ") stands in for the fitted sheen (colour " + detail::rgbText(m.sheenColour) +
           ", roughness " + num(m.sheenRoughness) + "): the sheen colour x (" +
           num(a.diffuseScale) + " x its diffuse with retro-reflection at roughness " +
           num(a.roughness) + " + " + num(a.sheenScale) +
           " x its sheen), the least-squares nearest on the 81 x 81 grid; rms mismatch " +
           num(a.relativeMismatch) + " of the sheen's (1 = leaving it out)"});
}

std::string sheenSceneText(const fit::FittedMaterial& m, const std::string& source,
                           const Blend& b, const SheenPart& p) {
  std::ostringstream x;
  x << "  <!-- slicecap_fit = blendbsdf weight c = " << num(p.weight)
    << ": (1 - c) x the diffuse + GGX above divided by\n"
    << "       (1 - c), + c x a principled BSDF (no specular) whose diffuse with retro-reflection"
    << (p.sheen > 0.0 ? " and sheen" : "") << "\n"
    << "       stand in for the fitted Charlie sheen (colour " << detail::rgbText(m.sheenColour)
    << ", roughness " << num(m.sheenRoughness) << "),\n"
    << "       rms mismatch " << num(p.approximation.relativeMismatch)
    << " of the sheen's (docs/material-export.md). -->\n"
    << "  <bsdf type=\"blendbsdf\" id=\"slicecap_fit\">\n"
    << "    <float name=\"weight\" value=\"" << num(p.weight) << "\"/>\n"
    << baseBsdf(m, b, "    ", "")
    << "    <bsdf type=\"principled\">\n"
    << "      " << rgbElement("base_color", p.baseColour) << "\n"
    << "      <float name=\"roughness\" value=\"" << num(p.approximation.roughness) << "\"/>\n"
    << "      <float name=\"specular\" value=\"0\"/>\n"
    << "      <float name=\"main_specular_sampling_rate\" value=\"0\"/>\n";
  if (p.sheen > 0.0)
    x << "      <float name=\"sheen\" value=\"" << num(p.sheen) << "\"/>\n"
      << "      <float name=\"sheen_tint\" value=\"1\"/>\n";
  x << "    </bsdf>\n"
    << "  </bsdf>\n";
  return header(m, source) + x.str() + sampleShape(m);
}

}  // namespace

MitsubaExport mitsubaSnippet(const fit::FittedMaterial& fitted, const std::string& source) {
  const fit::FittedMaterial m = fitted.canonical();
  MitsubaExport out;
  out.report.format = "Mitsuba 3";
  const Blend blend = blendOf(m);
  if (m.model == fit::MaterialModel::GgxSheen) {
    const SheenPart sheen = sheenPartOf(m);
    if (sheen.weight > kNegligible) {
      const Blend scaledBlend = blendOf(scaledBy(m, 1.0 - sheen.weight));
      addLosses(m, scaledBlend, 1.0 - sheen.weight, out.report.losses);
      addSheenLoss(m, sheen, out.report.losses);
      out.text = sheenSceneText(m, source, scaledBlend, sheen);
      return out;
    }
  }
  addLosses(m, blend, 1.0, out.report.losses);
  if (m.model == fit::MaterialModel::GgxSheen)
    out.report.losses.push_back(
        {LossKind::SheenDropped, "the least-squares stand-in for the fitted sheen (colour " +
                                     detail::rgbText(m.sheenColour) +
                                     ") in Mitsuba's principled BSDF is zero: it is left out"});
  out.text = sceneText(m, source, blend);
  return out;
}

ExportReport writeMitsuba(const std::filesystem::path& path, const fit::FittedMaterial& material,
                          const std::string& source) {
  const MitsubaExport e = mitsubaSnippet(material, source);
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << e.text; });
  return e.report;
}

}  // namespace slicecap::material_export
