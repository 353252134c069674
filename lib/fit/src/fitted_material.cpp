// Evaluation, tabulation and the canonical convention of a fitted material.
#include "slicecap/fit/fitted_material.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include "lobe_terms.hpp"
#include "slicecap/core/angles.hpp"

namespace slicecap::fit {

std::string_view toString(MaterialModel model) {
  switch (model) {
    case MaterialModel::GgxSheen: return "ggx+sheen";
    case MaterialModel::GgxCoat: return "ggx+coat";
    case MaterialModel::GgxSheenCoat: return "ggx+sheen+coat";
    case MaterialModel::Ggx: break;
  }
  return "ggx";
}

std::string_view toString(SheenForm form) {
  return form == SheenForm::Additive ? "additive" : "khr_materials_sheen";
}

bool hasSheen(MaterialModel model) {
  return model == MaterialModel::GgxSheen || model == MaterialModel::GgxSheenCoat;
}

bool hasCoat(MaterialModel model) {
  return model == MaterialModel::GgxCoat || model == MaterialModel::GgxSheenCoat;
}

MaterialModel modelWith(bool sheen, bool coat) {
  if (sheen) return coat ? MaterialModel::GgxSheenCoat : MaterialModel::GgxSheen;
  return coat ? MaterialModel::GgxCoat : MaterialModel::Ggx;
}

Rgb FittedMaterial::evaluate(const UnitVector& toLight, const UnitVector& toView) const {
  const detail::PairGeometry g = detail::pairGeometry(toLight, toView);
  const double t = degToRad(tangentDeg);
  const double specular =
      detail::ggxSpecular(g, alphaTangent, alphaBitangent, std::cos(t), std::sin(t));
  const bool withSheen = hasSheen(model);
  const bool khr = withSheen && sheenForm == SheenForm::Khr;
  const double sheen =
      !withSheen ? 0.0
      : khr      ? detail::khrSheenLobe(g, sheenRoughness)
                 : detail::sheenLobe(g, sheenRoughness);
  // KHR_materials_sheen's albedo scaling of everything under the sheen.
  const double baseScaling =
      khr ? 1.0 - sheenColour.maxChannel() * detail::khrSheenAlbedoMax(g, sheenRoughness) : 1.0;
  const bool coat = hasCoat(model);
  const double coatShare = coat ? coatWeight * g.coatFresnel : 0.0;
  const double coatLobe = coat ? detail::ggxSpecular(g, coatAlpha, coatAlpha, 1.0, 0.0) : 0.0;
  Rgb value;
  for (std::size_t c = 0; c < 3; ++c) {
    const double base =
        (diffuseAlbedo[c] / std::numbers::pi +
         (specularF0[c] + (specularF90 - specularF0[c]) * g.fresnelWeight) * specular) *
            baseScaling +
        sheenColour[c] * sheen;
    value[c] = base * (1.0 - coatShare) + coatShare * coatLobe;
  }
  return value;
}

FittedMaterial FittedMaterial::canonical() const {
  FittedMaterial m = *this;
  if (m.alphaTangent < m.alphaBitangent) {
    std::swap(m.alphaTangent, m.alphaBitangent);
    m.tangentDeg += 90.0;
  }
  m.tangentDeg = std::fmod(m.tangentDeg, 180.0);
  if (m.tangentDeg < 0.0) m.tangentDeg += 180.0;
  if (m.tangentDeg >= 180.0) m.tangentDeg = 0.0;  // -tiny + 180 rounding up
  return m;
}

Abrdf tabulate(const FittedMaterial& material) {
  return tabulateOnGrid(
      [&material](const UnitVector& l, const UnitVector& v) { return material.evaluate(l, v); });
}

double tangentDifferenceDeg(double aDeg, double bDeg) {
  double d = std::fmod(aDeg - bDeg, 180.0);
  if (d <= -90.0) d += 180.0;
  if (d > 90.0) d -= 180.0;
  return d;
}

}  // namespace slicecap::fit
