// The texture fit's solve with a tilted shading normal: the GGX block (no sheen) and the tilt,
// bounded as solveFromStart plus the tilt's bound.
#pragma once

#include <array>

#include "start_solver.hpp"
#include "tilted_cost.hpp"

namespace slicecap::fit::detail {

/// \brief The tilt's bound: |x|, |y| <= 0.5 for the normal's x and y, so a tilt of up to 30 deg
/// along the texel's axes and 45 deg on the diagonals (woven and brushed relief stays well inside;
/// beyond it the grid's 75 deg views fall behind the tilted surface).
inline constexpr double kMaximumTiltComponent = 0.5;

struct TiltedParameters {
  std::array<double, kGgxParameters> ggx{};
  std::array<double, kTiltParameters> tilt{};  ///< shading normal x, y; {0, 0} is flat
};

struct TiltedOutcome {
  TiltedParameters parameters;
  bool converged = false;  ///< Ceres ended with CONVERGENCE and a finite cost
  double cost = 0.0;       ///< 1/2 sum of squared residuals
};

/// \brief Solves TiltedCost from `start` (as solveFromStart: same tolerances meaning, same GGX
/// bounds, the tilt's components within +-kMaximumTiltComponent). Never throws for a bad fit.
TiltedOutcome solveTiltedFromStart(const FitData& data, const TiltedParameters& start,
                                   int maxIterations, double functionTolerance,
                                   double initialTrustRegionRadius);

/// \brief The GGX block of `p` with the tilt `tilt`, and back (the tilt dropped).
TiltedParameters withTilt(const FitParameters& p, const std::array<double, kTiltParameters>& tilt);
FitParameters withoutTilt(const TiltedParameters& p);

/// \brief `p` with alpha_t >= alpha_b, the same BRDF: where they are the other way round they are
/// swapped and the tangent turned to the old bitangent's direction. Under a tilt that is not the
/// untilted azimuth + 90 deg (projection onto the tilted plane does not keep right angles): it is
/// the azimuth in the untilted plane whose projection is n' x t'. FittedMaterial::canonical() then
/// only wraps the azimuth into [0, 180), which a projection keeps.
TiltedParameters canonicalTilted(TiltedParameters p);

/// \brief The shading normal of a tilt: (x, y, sqrt(1 - x^2 - y^2)).
UnitVector shadingNormalOf(const std::array<double, kTiltParameters>& tilt);

/// \brief Whether the GGX block's specular lobe is strong enough to locate a tilt: its peak
/// f0max / (4 pi alpha_t alpha_b) (D G2 / 4 at normal incidence) is at least
/// kMinimumLobeToDiffuse times the diffuse albedo's largest channel / pi, and positive. Below it
/// (no lobe: f0 ~ 0; a lobe spread over the hemisphere: alphas ~ 1; f0 0.04 with alphas 1 over
/// albedo 0.5 is 0.02) the only cue left is the diffuse cosine, where real surfaces depart from
/// Lambert's (retro-reflection, rough diffusers): a tilt fitted to it would read that as relief.
/// The benchmark's roughest texel (alphas 0.3 and 1.2, f0 0.05, albedo 0.54) is at 0.065.
bool lobeLocatesTilt(const std::array<double, kGgxParameters>& ggx);
inline constexpr double kMinimumLobeToDiffuse = 0.03;

/// \brief RMS residual of `p` on `data`, 8-bit sRGB levels.
double tiltedRmseLevels(const FitData& data, const TiltedParameters& p);

}  // namespace slicecap::fit::detail
