// The GGX stand-in for the Charlie sheen: its lobe is Mitsuba's roughconductor formula, its scale
// and alpha are the least-squares optimum on the grid within the room given, and it is much
// nearer the sheen than leaving it out.
#include "slicecap/material_export/mitsuba_sheen.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::material_export {
namespace {

UnitVector at(double thetaDeg, double phiDeg) {
  return toUnitVector({thetaDeg, phiDeg});
}

// rms(scale x stand-in - Charlie) / rms(Charlie) over the grid, computed here independently.
double mismatch(double roughness, double alpha, double scale) {
  fit::FittedMaterial sheen;
  sheen.model = fit::MaterialModel::GgxSheen;
  sheen.specularF0 = Rgb::gray(0.0);
  sheen.specularF90 = 0.0;
  sheen.sheenColour = Rgb::gray(1.0);
  sheen.sheenRoughness = roughness;
  double residual = 0.0, total = 0.0;
  for (int i = 0; i < bonn::kDirectionCount; ++i) {
    for (int j = 0; j < bonn::kDirectionCount; ++j) {
      const UnitVector l = toUnitVector(bonn::direction(i)), v = toUnitVector(bonn::direction(j));
      const double charlie = sheen.evaluate(l, v)[0], w2 = l.z * l.z;
      residual += w2 * std::pow(scale * ggxStandInLobe(l, v, alpha) - charlie, 2.0);
      total += w2 * charlie * charlie;
    }
  }
  return std::sqrt(residual / total);
}

TEST(MitsubaSheen, StandInLobeIsGgxWithSeparableSmith) {
  // Face on: D(n) = 1 / (pi alpha^2), G1 = 1, so f = 1 / (4 pi alpha^2).
  for (double alpha : {0.5, 1.0, 2.0})
    EXPECT_NEAR(ggxStandInLobe(at(0, 0), at(0, 0), alpha),
                1.0 / (4.0 * std::numbers::pi * alpha * alpha), 1e-12);
  // Mirror pair at 60 deg: h = n, G1(60 deg) = 2 / (1 + sqrt(1 + 3 alpha^2)).
  const double alpha = 1.5, g1 = 2.0 / (1.0 + std::sqrt(1.0 + 3.0 * alpha * alpha));
  EXPECT_NEAR(ggxStandInLobe(at(60, 0), at(60, 180), alpha),
              g1 * g1 / (std::numbers::pi * alpha * alpha * 4.0 * 0.25), 1e-12);
  EXPECT_EQ(ggxStandInLobe(at(60, 0), UnitVector{0.0, 0.6, -0.8}, alpha), 0.0);
}

TEST(MitsubaSheen, ScaleAndAlphaAreTheLeastSquaresOptimum) {
  const double roughness = 0.3;
  const SheenApproximation a = approximateSheen(roughness, 100.0);  // room enough: unconstrained
  EXPECT_NEAR(a.relativeMismatch, mismatch(roughness, a.alpha, a.scale), 1e-9);
  for (double f : {0.98, 1.02})
    EXPECT_GT(mismatch(roughness, a.alpha, a.scale * f), a.relativeMismatch);
  for (double d : {-0.05, 0.05}) {  // the neighbouring alphas at their own best scale do worse
    double best = 1.0;
    for (int k = 50; k <= 150; ++k)
      best = std::min(best, mismatch(roughness, a.alpha + d, a.scale * k / 100.0));
    EXPECT_GT(best, a.relativeMismatch);
  }
  // Much nearer the sheen than leaving it out (1); measured 0.28 at roughness 0.3.
  EXPECT_LT(a.relativeMismatch, 0.5);
}

TEST(MitsubaSheen, ScaleStaysWithinTheRoomGiven) {
  const SheenApproximation free = approximateSheen(0.25, 100.0);
  const SheenApproximation bound = approximateSheen(0.25, 0.5 * free.scale);
  EXPECT_NEAR(bound.scale, 0.5 * free.scale, 1e-12);
  EXPECT_GT(bound.relativeMismatch, free.relativeMismatch);
  const SheenApproximation none = approximateSheen(0.25, -0.1);
  EXPECT_EQ(none.scale, 0.0);
  EXPECT_NEAR(none.relativeMismatch, 1.0, 1e-12);
}

}  // namespace
}  // namespace slicecap::material_export
