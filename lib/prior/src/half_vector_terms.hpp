// Anisotropy as a function of the half vector: the terms the prior adds for anisotropic samples.
#pragma once

#include <array>

#include "slicecap/core/grid.hpp"

namespace slicecap::prior {

/// \brief Hat functions of the half vector's elevation (nodes 15..90 deg, width 15 deg): first
/// alone (kIsotropicTermCount isotropic terms), then times cos(2 m phi_h) and sin(2 m phi_h),
/// m = 1, 2. Why: a microfacet material's anisotropy lives in
/// its normal distribution, a function of the half vector (Ward, anisotropic GGX: log D is
/// tan^2(theta_h) times a cos(2 phi_h) term), so what the axial slices measure at theta_h ~ 30, 52
/// and 75 deg carries to every other light and view pair through h. The isotropic hats let the
/// isotropic fit absorb what the learned basis misses along theta_h (analytic lobes unlike the
/// measured tables), so that the anisotropic terms are chosen only for anisotropy.
inline constexpr int kIsotropicTermCount = 6;
inline constexpr int kHalfVectorTermCount = 30;

using HalfVectorTerms = std::array<double, kHalfVectorTermCount>;

/// \brief The terms of a light and view direction.
HalfVectorTerms halfVectorTerms(const UnitVector& light, const UnitVector& view);

/// \brief The terms of every grid entry [light][view], computed once.
const std::array<HalfVectorTerms, 81 * 81>& gridHalfVectorTerms();

}  // namespace slicecap::prior
