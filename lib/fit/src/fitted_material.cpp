// Evaluation, tabulation and the canonical convention of a fitted material.
#include "slicecap/fit/fitted_material.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include "lobe_terms.hpp"
#include "slicecap/core/angles.hpp"

namespace slicecap::fit {

std::string_view toString(MaterialModel model) {
  return model == MaterialModel::GgxSheen ? "ggx+sheen" : "ggx";
}

Rgb FittedMaterial::evaluate(const UnitVector& toLight, const UnitVector& toView) const {
  const detail::PairGeometry g = detail::pairGeometry(toLight, toView);
  const double t = degToRad(tangentDeg);
  const double specular =
      detail::ggxSpecular(g, alphaTangent, alphaBitangent, std::cos(t), std::sin(t));
  const double sheen =
      model == MaterialModel::GgxSheen ? detail::sheenLobe(g, sheenRoughness) : 0.0;
  Rgb value;
  for (std::size_t c = 0; c < 3; ++c) {
    value[c] = diffuseAlbedo[c] / std::numbers::pi +
               (specularF0[c] + (specularF90 - specularF0[c]) * g.fresnelWeight) * specular +
               sheenColour[c] * sheen;
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
