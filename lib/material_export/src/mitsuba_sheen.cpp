// The least-squares stand-in for the Charlie sheen in Mitsuba 3's principled BSDF (why these two
// terms: docs/material-export.md, Mitsuba section).
#include "slicecap/material_export/mitsuba_sheen.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::material_export {
namespace {

double schlickWeight(double cosine) { return std::pow(std::clamp(1.0 - cosine, 0.0, 1.0), 5.0); }

// cos of the angle between the half vector and the light (equal to the view's).
double cosDifference(const UnitVector& l, const UnitVector& v) {
  const double hx = l.x + v.x, hy = l.y + v.y, hz = l.z + v.z;
  const double length = std::sqrt(hx * hx + hy * hy + hz * hz);
  return length > 0.0 ? std::abs(hx * l.x + hy * l.y + hz * l.z) / length : 1.0;
}

// One grid pair's weighted values: the Charlie lobe and the two principled terms.
struct Sample {
  double weight, charlie, diffuse, sheen;
};

std::vector<Sample> samples(double charlieRoughness, double roughness) {
  fit::FittedMaterial lobe;  // the sheen alone: no diffuse, no specular, colour 1
  lobe.model = fit::MaterialModel::GgxSheen;
  lobe.specularF0 = Rgb::gray(0.0);
  lobe.specularF90 = 0.0;
  lobe.sheenColour = Rgb::gray(1.0);
  lobe.sheenRoughness = charlieRoughness;
  std::vector<Sample> out;
  out.reserve(bonn::kDirectionCount * bonn::kDirectionCount);
  for (int i = 0; i < bonn::kDirectionCount; ++i) {
    const UnitVector l = toUnitVector(bonn::direction(i));
    for (int j = 0; j < bonn::kDirectionCount; ++j) {
      const UnitVector v = toUnitVector(bonn::direction(j));
      out.push_back({l.z, lobe.evaluate(l, v)[0], principledDiffuseLobe(l, v, roughness),
                     principledSheenLobe(l, v)});
    }
  }
  return out;
}

// Non-negative least squares of two columns: the unconstrained solution if both are >= 0, else
// the better of the two one-column fits (with a 2 x 2 system that is the whole active-set search).
SheenApproximation solve(const std::vector<Sample>& s, double roughness) {
  double aa = 0, ab = 0, bb = 0, ay = 0, by = 0, yy = 0;
  for (const Sample& x : s) {
    const double w2 = x.weight * x.weight;
    aa += w2 * x.diffuse * x.diffuse;
    ab += w2 * x.diffuse * x.sheen;
    bb += w2 * x.sheen * x.sheen;
    ay += w2 * x.diffuse * x.charlie;
    by += w2 * x.sheen * x.charlie;
    yy += w2 * x.charlie * x.charlie;
  }
  const auto residual = [&](double a, double b) {
    return aa * a * a + 2 * ab * a * b + bb * b * b - 2 * (ay * a + by * b) + yy;
  };
  std::array<std::array<double, 2>, 3> candidates{{{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}}};
  const double det = aa * bb - ab * ab;
  if (det > 0.0) candidates[0] = {(ay * bb - by * ab) / det, (by * aa - ay * ab) / det};
  if (aa > 0.0) candidates[1] = {std::max(ay / aa, 0.0), 0.0};
  if (bb > 0.0) candidates[2] = {0.0, std::max(by / bb, 0.0)};
  SheenApproximation best;
  double bestResidual = yy;
  for (const auto& [a, b] : candidates) {
    if (a < 0.0 || b < 0.0 || residual(a, b) >= bestResidual) continue;
    bestResidual = residual(a, b);
    best = {a, roughness, b, 0.0};
  }
  best.roughness = roughness;
  best.relativeMismatch = yy > 0.0 ? std::sqrt(std::max(bestResidual, 0.0) / yy) : 0.0;
  return best;
}

}  // namespace

double principledDiffuseLobe(const UnitVector& toLight, const UnitVector& toView,
                             double roughness) {
  const double fl = schlickWeight(toLight.z), fv = schlickWeight(toView.z);
  const double cosD = cosDifference(toLight, toView);
  const double retro = 2.0 * roughness * cosD * cosD;
  return ((1.0 - 0.5 * fl) * (1.0 - 0.5 * fv) + retro * (fl + fv + fl * fv * (retro - 1.0))) /
         std::numbers::pi;
}

double principledSheenLobe(const UnitVector& toLight, const UnitVector& toView) {
  return schlickWeight(cosDifference(toLight, toView));
}

SheenApproximation approximateSheen(double charlieRoughness) {
  SheenApproximation best;
  constexpr int kSteps = 20;  // principled roughness 0, 0.05, ..., 1
  for (int k = 0; k <= kSteps; ++k) {
    const SheenApproximation a = solve(samples(charlieRoughness, k / double(kSteps)), k / double(kSteps));
    if (k == 0 || a.relativeMismatch < best.relativeMismatch) best = a;
  }
  return best;
}

}  // namespace slicecap::material_export
