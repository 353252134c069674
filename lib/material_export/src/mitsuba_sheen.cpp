// The least-squares GGX stand-in for the Charlie sheen in a Mitsuba 3 snippet (why this lobe:
// docs/material-export.md, Mitsuba section).
#include "slicecap/material_export/mitsuba_sheen.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::material_export {
namespace {

// Smith's G1 of isotropic GGX for a direction of this cosine (Mitsuba's smith_g1; the half vector
// of two directions above the surface is always on their side).
double smithG1(double cosTheta, double alpha) {
  const double tan2 = (1.0 - cosTheta * cosTheta) / (cosTheta * cosTheta);
  return 2.0 / (1.0 + std::sqrt(1.0 + alpha * alpha * tan2));
}

// One grid pair: its weight and the Charlie lobe there.
struct Pair {
  UnitVector light, view;
  double weight, charlie;
};

std::vector<Pair> gridPairs(double charlieRoughness, fit::SheenForm form) {
  fit::FittedMaterial lobe;  // the sheen alone: no diffuse, no specular, colour 1
  lobe.model = fit::MaterialModel::GgxSheen;
  lobe.specularF0 = Rgb::gray(0.0);
  lobe.specularF90 = 0.0;
  lobe.sheenColour = Rgb::gray(1.0);
  lobe.sheenRoughness = charlieRoughness;
  lobe.sheenForm = form;
  std::vector<Pair> out;
  out.reserve(bonn::kDirectionCount * bonn::kDirectionCount);
  for (int i = 0; i < bonn::kDirectionCount; ++i) {
    const UnitVector l = toUnitVector(bonn::direction(i));
    for (int j = 0; j < bonn::kDirectionCount; ++j) {
      const UnitVector v = toUnitVector(bonn::direction(j));
      out.push_back({l, v, l.z, lobe.evaluate(l, v)[0]});
    }
  }
  return out;
}

// The best scale in [0, maxScale] for one alpha: the unconstrained one clamped (one variable, a
// convex quadratic).
SheenApproximation fitAlpha(const std::vector<Pair>& pairs, double alpha, double maxScale) {
  double gg = 0.0, gc = 0.0, cc = 0.0;
  for (const Pair& p : pairs) {
    const double w2 = p.weight * p.weight, g = ggxStandInLobe(p.light, p.view, alpha);
    gg += w2 * g * g;
    gc += w2 * g * p.charlie;
    cc += w2 * p.charlie * p.charlie;
  }
  SheenApproximation a;
  a.alpha = alpha;
  a.scale = gg > 0.0 ? std::clamp(gc / gg, 0.0, std::max(maxScale, 0.0)) : 0.0;
  const double residual = gg * a.scale * a.scale - 2.0 * gc * a.scale + cc;
  a.relativeMismatch = cc > 0.0 ? std::sqrt(std::max(residual, 0.0) / cc) : 0.0;
  return a;
}

}  // namespace

double ggxStandInLobe(const UnitVector& toLight, const UnitVector& toView, double alpha) {
  if (toLight.z <= 0.0 || toView.z <= 0.0) return 0.0;
  const double hx = toLight.x + toView.x, hy = toLight.y + toView.y, hz = toLight.z + toView.z;
  const double cosH2 = hz * hz / (hx * hx + hy * hy + hz * hz);
  const double a2 = alpha * alpha;
  const double d = 1.0 / (std::numbers::pi * a2 * cosH2 * cosH2 *
                          std::pow(1.0 + (1.0 - cosH2) / (cosH2 * a2), 2.0));
  return d * smithG1(toLight.z, alpha) * smithG1(toView.z, alpha) / (4.0 * toLight.z * toView.z);
}

SheenApproximation approximateSheen(double charlieRoughness, double maxScale, fit::SheenForm form) {
  const std::vector<Pair> pairs = gridPairs(charlieRoughness, form);
  SheenApproximation best;
  constexpr int kSteps = 60;  // alpha 0.05, 0.10, ..., 3: beyond 3 the masking darkens it again
  for (int k = 1; k <= kSteps; ++k) {
    const SheenApproximation a = fitAlpha(pairs, 0.05 * k, maxScale);
    if (k == 1 || a.relativeMismatch < best.relativeMismatch) best = a;
  }
  return best;
}

}  // namespace slicecap::material_export
