// The fit as Mitsuba 3 XML: blendbsdf(diffuse, roughconductor) weighted so that the blend is a sum,
// for a sheen fit a GGX stand-in for the sheen blended in the same way, and for a coat fit the
// coat's lobe blended around all of it.
#include "slicecap/material_export/mitsuba_writer.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "slicecap/fit/sheen_albedo.hpp"
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
    << "     <ref id=\"slicecap_fit\"/>; its anisotropy follows each shape's dp/du."
    << (fit::hasCoat(m.model) && m.coatWeight > kNegligible
            ? "\n     The fit's clear coat is blended around all of it (below).": "")
    << " -->\n"
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

// The GGX lobe standing in for the sheen and its blend weight c (docs/material-export.md): the
// snippet is (1 - c) x [the diffuse + GGX blend of the fit scaled by 1 / (1 - c)] + c x the
// stand-in, so the stand-in's reflectance is the approximation's divided by c. c is the smallest
// that keeps that reflectance within [0, 1] (its largest channel 1), leaving the most room for the
// rest; the approximation's scale is bounded so that the rest still fits (f0 + albedo <= 1 - c).
struct SheenPart {
  SheenApproximation approximation;
  double weight = 0.0;
  Rgb reflectance;
};

SheenPart sheenPartOf(const fit::FittedMaterial& m) {
  SheenPart p;
  const double colourMax = m.sheenColour.maxChannel();
  if (colourMax <= kNegligible) return p;
  const double room = 1.0 - m.diffuseAlbedo.maxChannel() - m.specularF0.maxChannel();
  p.approximation = approximateSheen(m.sheenRoughness, room / colourMax, m.sheenForm);
  p.weight = std::min(1.0, p.approximation.scale * colourMax);
  if (p.weight <= kNegligible) return p;
  for (std::size_t c = 0; c < 3; ++c) p.reflectance[c] = m.sheenColour[c] / colourMax;
  return p;
}

// KHR_materials_sheen's dimming of the base, 1 - s max(E(cos_l), E(cos_v)) (the khr sheen
// form), as one number: its mean over the 81 x 81 grid pairs weighted by cos(light) (the rendered
// radiance, as the stand-in's own fit). A blend cannot make it depend on the directions.
double meanSheenScaling(const fit::FittedMaterial& m) {
  double sum = 0.0, weights = 0.0;
  const double colourMax = m.sheenColour.maxChannel();
  for (int i = 0; i < bonn::kDirectionCount; ++i) {
    const UnitVector l = toUnitVector(bonn::direction(i));
    for (int j = 0; j < bonn::kDirectionCount; ++j) {
      const UnitVector v = toUnitVector(bonn::direction(j));
      const double albedo = std::max(fit::sheenAlbedo(l.z, m.sheenRoughness),
                                     fit::sheenAlbedo(v.z, m.sheenRoughness));
      sum += l.z * (1.0 - colourMax * albedo);
      weights += l.z;
    }
  }
  return sum / weights;
}

// The khr form's base dimmed by meanSheenScaling; the additive form's as it is.
fit::FittedMaterial baseUnderSheen(fit::FittedMaterial m) {
  if (!fit::hasSheen(m.model) || m.sheenForm != fit::SheenForm::Khr) return m;
  const double scaling = meanSheenScaling(m);
  for (std::size_t c = 0; c < 3; ++c) {
    m.diffuseAlbedo[c] *= scaling;
    m.specularF0[c] *= scaling;
  }
  m.specularF90 *= scaling;
  return m;
}

// The fit's diffuse, specular and sheen divided by `factor`: the rest of a blend whose other part
// takes the share 1 - factor. A factor of 0 (that part takes the whole blend, which the room allows
// only when there is nothing else) leaves them 0.
fit::FittedMaterial scaledBy(fit::FittedMaterial m, double factor) {
  const auto divide = [factor](double v) { return factor > 0.0 ? v / factor : 0.0; };
  for (std::size_t c = 0; c < 3; ++c) {
    m.diffuseAlbedo[c] = divide(m.diffuseAlbedo[c]);
    m.specularF0[c] = divide(m.specularF0[c]);
    m.sheenColour[c] = divide(m.sheenColour[c]);
  }
  m.specularF90 = divide(m.specularF90);
  return m;
}

// `share`: the sheen blend's share of the snippet (1 - the coat's weight; 1 without a coat).
void addSheenLoss(const fit::FittedMaterial& m, const SheenPart& p, double share,
                  std::vector<ConversionLoss>& losses) {
  const SheenApproximation& a = p.approximation;
  losses.push_back(
      {LossKind::SheenForm,
       "Mitsuba 3 has no Charlie sheen BSDF: the fitted sheen (colour " +
           detail::rgbText(m.sheenColour) + ", roughness " + num(m.sheenRoughness) +
           ") is approximated by a GGX lobe of alpha " + num(a.alpha) + " and Fresnel 1 (" +
           num(a.scale) + " x the sheen colour; weight " + num(share * p.weight) + " of the snippet" +
           "), the least-squares nearest on the 81 x 81 grid: rms mismatch " +
           num(a.relativeMismatch) + " of the sheen's (1 = leaving it out)"});
}

// The sheen blend (see SheenPart), each line indented by `indent`.
std::string sheenBsdf(const fit::FittedMaterial& m, const Blend& b, const SheenPart& p,
                      const std::string& indent, const std::string& idAttribute) {
  std::ostringstream x;
  x << indent << "<!-- blendbsdf weight c = " << num(p.weight)
    << ": (1 - c) x the diffuse + GGX, divided by (1 - c), + c x a GGX\n"
    << indent << "     lobe of Fresnel 1 standing in for the fitted Charlie sheen (colour "
    << detail::rgbText(m.sheenColour) << ",\n"
    << indent << "     roughness " << num(m.sheenRoughness) << "); rms mismatch "
    << num(p.approximation.relativeMismatch)
    << " of the sheen's (docs/material-export.md). -->\n"
    << indent << "<bsdf type=\"blendbsdf\"" << idAttribute << ">\n"
    << indent << "  <float name=\"weight\" value=\"" << num(p.weight) << "\"/>\n"
    << baseBsdf(m, b, indent + "  ", "")
    << indent << "  <bsdf type=\"roughconductor\">\n"
    << indent << "    <string name=\"material\" value=\"none\"/>\n"
    << indent << "    <string name=\"distribution\" value=\"ggx\"/>\n"
    << indent << "    <float name=\"alpha\" value=\"" << num(p.approximation.alpha) << "\"/>\n"
    << indent << "    " << rgbElement("specular_reflectance", p.reflectance) << "\n"
    << indent << "  </bsdf>\n"
    << indent << "</bsdf>\n";
  return x.str();
}

// The diffuse + GGX (+ sheen stand-in) BSDF of `m`, whose share of the snippet is `scale` (1
// without a coat); the losses are reported against `fitted`, the material as fitted.
std::string fitBsdf(const fit::FittedMaterial& fitted, const fit::FittedMaterial& m, double scale,
                    const std::string& indent, const std::string& idAttribute,
                    std::vector<ConversionLoss>& losses) {
  if (fit::hasSheen(fitted.model) && fitted.sheenForm == fit::SheenForm::Khr &&
      fitted.sheenColour.maxChannel() > kNegligible)
    losses.push_back({LossKind::SheenForm,
                      "Mitsuba 3 cannot dim the base by the sheen's directional albedo "
                      "(KHR_materials_sheen's 1 - s E): the diffuse and specular are scaled by its "
                      "mean over the grid, " + num(meanSheenScaling(fitted))});
  if (fit::hasSheen(m.model)) {
    const SheenPart sheen = sheenPartOf(m);
    if (sheen.weight > kNegligible) {
      const Blend scaledBlend = blendOf(scaledBy(m, 1.0 - sheen.weight));
      addLosses(fitted, scaledBlend, scale * (1.0 - sheen.weight), losses);
      addSheenLoss(fitted, sheen, scale, losses);
      return sheenBsdf(fitted, scaledBlend, sheen, indent, idAttribute);
    }
  }
  const Blend blend = blendOf(m);
  addLosses(fitted, blend, scale, losses);
  if (fit::hasSheen(m.model))
    losses.push_back(
        {LossKind::SheenDropped,
         "the fitted sheen (colour " + detail::rgbText(fitted.sheenColour) +
             ") is left out: its least-squares GGX stand-in is zero, or the diffuse and specular" +
             (scale < 1.0 ? std::string(", with the coat blended around them,") : std::string()) +
             " leave it no room"});
  return baseBsdf(m, blend, indent, idAttribute);
}

// The coat's blend weight c: the coat's weight w (its reflectance at grazing, where the fit's
// Fc is 1 and roughconductor's Fresnel is 1), as far as the rest, divided by (1 - c), stays within
// Mitsuba's reflectances of at most 1.
double coatBlendWeight(const fit::FittedMaterial& m) {
  const double room = 1.0 - m.diffuseAlbedo.maxChannel() - m.specularF0.maxChannel();
  return std::clamp(std::min(m.coatWeight, room), 0.0, 1.0);
}

// The fit's coat: blendbsdf(c, the rest divided by (1 - c), a roughconductor of eta 1.5, k 0:
// the exact Fresnel of the coat's dielectric, 0.04 at normal incidence, 1 at grazing).
std::string coatedBsdf(const fit::FittedMaterial& m, double c, std::vector<ConversionLoss>& losses) {
  // The khr sheen's dimming of the base first (with the fit's own sheen colour), then the blend's.
  const fit::FittedMaterial inner = scaledBy(baseUnderSheen(m), 1.0 - c);
  std::ostringstream x;
  x << "  <!-- slicecap_fit = blendbsdf weight c = " << num(c)
    << ": (1 - c) x the fit without its coat, divided by (1 - c),\n"
    << "       + c x the coat: GGX alpha " << num(m.coatAlpha)
    << " with the exact Fresnel of IOR 1.5 (fit: weight " << num(m.coatWeight) << "). -->\n"
    << "  <bsdf type=\"blendbsdf\" id=\"slicecap_fit\">\n"
    << "    <float name=\"weight\" value=\"" << num(c) << "\"/>\n"
    << fitBsdf(m, inner, 1.0 - c, "    ", "", losses)
    << "    <bsdf type=\"roughconductor\">\n"
    << "      <string name=\"distribution\" value=\"ggx\"/>\n"
    << "      <float name=\"alpha\" value=\"" << num(m.coatAlpha) << "\"/>\n"
    << "      " << rgbElement("eta", Rgb::gray(1.5)) << "\n"
    << "      " << rgbElement("k", Rgb::gray(0.0)) << "\n"
    << "    </bsdf>\n"
    << "  </bsdf>\n";
  losses.push_back({LossKind::CoatForm,
                    "Mitsuba 3 has no layered coat: the coat is blended in with weight " + num(c) +
                        ", its Fresnel the exact one of IOR 1.5 at each microfacet (the fit's: "
                        "Schlick's at the view's angle to the normal), and the rest is not dimmed "
                        "by it (the fit dims it by 1 - w Fc: " + num(1.0 - fit::kCoatF0 * m.coatWeight) +
                        " face on)"});
  if (c < m.coatWeight - 1e-6)
    losses.push_back({LossKind::CoatForm,
                      "coat weight " + num(m.coatWeight) + " reduced to " + num(c) +
                          ": the diffuse and specular, divided by (1 - c), leave it no more room "
                          "within reflectances of 1"});
  return x.str();
}

}  // namespace

MitsubaExport mitsubaSnippet(const fit::FittedMaterial& fitted, const std::string& source) {
  const fit::FittedMaterial m = fitted.canonical();
  MitsubaExport out;
  out.report.format = "Mitsuba 3";
  std::string bsdf;
  if (fit::hasCoat(m.model) && m.coatWeight > kNegligible) {
    bsdf = coatedBsdf(m, coatBlendWeight(m), out.report.losses);
  } else {
    bsdf = fitBsdf(m, baseUnderSheen(m), 1.0, "  ", " id=\"slicecap_fit\"", out.report.losses);
  }
  out.text = header(m, source) + bsdf + sampleShape(m);
  return out;
}

ExportReport writeMitsuba(const std::filesystem::path& path, const fit::FittedMaterial& material,
                          const std::string& source) {
  const MitsubaExport e = mitsubaSnippet(material, source);
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << e.text; });
  return e.report;
}

}  // namespace slicecap::material_export
