// The onion parameterisation of Method A (docs/method.md §5.1): a seam-free map of the hemisphere.
#pragma once

#include <array>

#include "slicecap/core/grid.hpp"

namespace slicecap::recon {

/// \brief Onion angles of a direction, both in [-pi/2, pi/2]: b = asin(x), a = asin(y / cos b)
/// (a = 0 where cos b < 1e-5); inverse (sin b, sin a cos b, cos a cos b).
struct OnionAngles {
  double aRad = 0.0;
  double bRad = 0.0;
};

/// \brief The plain onion map of a direction.
OnionAngles onionAngles(const Direction& direction);

/// \brief The light's onion angles relative to the view azimuth (SRC-4's BTF branch): the
/// specular direction maps to (theta_v, 0), the retro direction to (-theta_v, 0).
OnionAngles onionAnglesRelativeToView(const Direction& light, double viewPhiDeg);

/// \brief How the light direction enters Method A's feature vector.
enum class OnionFrame {
  ViewRelative,  ///< light relative to the view azimuth (docs/method.md §5.1, default)
  Absolute,      ///< the plain map for both directions (the alternative docs/method.md §5.1 names)
};

/// \brief A point of the 4-D interpolation space, radians: (a_i, b_i, a_v, b_v).
using FeaturePoint = std::array<double, 4>;

/// \brief The feature vector of a light/view pair.
FeaturePoint onionFeatures(const Direction& light, const Direction& view,
                           OnionFrame frame = OnionFrame::ViewRelative);

}  // namespace slicecap::recon
