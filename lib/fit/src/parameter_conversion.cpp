// Parameter blocks <-> FittedMaterial, and a solution's RMS residual.
#include "parameter_conversion.hpp"

#include <cmath>
#include <vector>

#include "material_cost.hpp"
#include "slicecap/core/angles.hpp"

namespace slicecap::fit::detail {

FittedMaterial materialOf(const FitParameters& p) {
  FittedMaterial m;
  m.model = modelWith(p.withSheen, p.withCoat);
  m.diffuseAlbedo = {p.ggx[0], p.ggx[1], p.ggx[2]};
  m.specularF0 = {p.ggx[3], p.ggx[4], p.ggx[5]};
  m.alphaTangent = std::exp(p.ggx[6]);
  m.alphaBitangent = std::exp(p.ggx[7]);
  m.tangentDeg = radToDeg(p.ggx[8]);
  m.specularF90 = p.ggx[9];
  if (p.withSheen) {
    m.sheenColour = {p.sheen[0], p.sheen[1], p.sheen[2]};
    m.sheenRoughness = std::exp(p.sheen[3]);
    m.sheenForm = p.sheenForm;
  }
  if (p.withCoat) {
    m.coatWeight = p.coat[0];
    m.coatAlpha = std::exp(p.coat[1]);
  }
  return m.canonical();
}

FitParameters ggxParametersOf(const FittedMaterial& m) {
  FitParameters p;
  p.ggx = {m.diffuseAlbedo[0], m.diffuseAlbedo[1], m.diffuseAlbedo[2],
           m.specularF0[0],    m.specularF0[1],    m.specularF0[2],
           std::log(m.alphaTangent), std::log(m.alphaBitangent), degToRad(m.tangentDeg),
           m.specularF90};
  p.sheenForm = m.sheenForm;
  return p;
}

double rmseLevels(const FitData& data, const FitParameters& p) {
  const MaterialCost cost(data, p.withSheen, p.withCoat, p.sheenForm);
  std::vector<double> residuals(static_cast<std::size_t>(data.residualCount()));
  std::vector<const double*> blocks{p.ggx.data()};
  if (p.withSheen) blocks.push_back(p.sheen.data());
  if (p.withCoat) blocks.push_back(p.coat.data());
  cost.Evaluate(blocks.data(), residuals.data(), nullptr);
  double sum = 0.0;
  for (double r : residuals) sum += r * r;
  return std::sqrt(sum / static_cast<double>(residuals.size()));
}

}  // namespace slicecap::fit::detail
