// The LED as a point source fitted to the white reference areas: its position, its power, the
// irradiance it gives anywhere on the target.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::capture {

/// \brief A point in the target frame, millimetres (origin at the window centre, z out of the
/// material; the target lies in z = 0).
struct TargetPointMm {
  double x = 0.0, y = 0.0, z = 0.0;
};

/// \brief Linear radiance measured on a white reference area at a point of the target (camera
/// units, the same frame and exposure as the window).
struct ReferenceObservation {
  TargetPointMm point;
  Rgb radiance;
  Rgb albedo;  ///< the area's printed reflectance (target description)
  /// \brief The radiance's expected noise, one standard deviation per channel (same units). All
  /// observations with it positive: the fit weights each by it; else every one counts alike.
  Rgb sigma{};
};

/// \brief A point light: E(x) = intensity * cos(theta) / d^2 = intensity * z_led / |led - x|^3 on
/// the target plane. Radiance of a Lambertian area: albedo / pi * E.
struct PointLight {
  TargetPointMm positionMm;
  Rgb intensity;  ///< per channel, camera units x mm^2
  /// \brief Irradiance at a point of the target plane, per channel.
  Rgb irradianceAt(const TargetPointMm& point) const;
  /// \brief Direction to the light from a point of the target (degrees, target frame).
  Direction directionFrom(const TargetPointMm& point) const;
};

/// \brief The fit and how well it explains the reference areas.
struct LightFit {
  PointLight light;
  bool converged = false;
  double relativeResidualRms = 0.0;  ///< RMS of (model - measured) / measured over the observations
  /// \brief The same RMS with each relative residual weighted by its inverse relative variance
  /// (ReferenceObservation::sigma); equals relativeResidualRms without sigmas.
  double weightedResidualRms = 0.0;
  /// \brief What noise alone gives weightedResidualRms on average: sqrt(dof / sum of the weights),
  /// dof = 3 x observations - 6 (position, three intensities); 0 without sigmas. Noise alone
  /// makes dof x (weightedResidualRms / noiseResidualRms)^2 chi-square with dof degrees of freedom.
  double noiseResidualRms = 0.0;
  int degreesOfFreedom = 0;
  /// \brief One standard deviation of the light's direction as seen from the window centre
  /// (degrees), from the fit's covariance scaled by its residuals; infinite if it could not be
  /// computed. The reference areas span only a few centimetres at ~30 cm, so the direction is much
  /// less certain than the irradiance: prefer the rig's nominal direction unless this is small.
  double directionSigmaDeg = 0.0;
  std::string message;
};

/// \brief Options of the fit.
struct LightFitParams {
  /// \brief The nominal LED position (e.g. from the camera pose and the rig's geometry): the start,
  /// and the centre of a weak prior.
  TargetPointMm initialPositionMm{0.0, 0.0, 300.0};
  /// \brief Weight of the prior: a displacement of the whole nominal distance costs as much as one
  /// observation off by this fraction. The references barely constrain the distance (a far light
  /// looks like a slightly dimmer near one), so without it the fit can drift away along that
  /// valley.
  double priorWeight = 0.05;
  int maxIterations = 200;
  /// \brief False, with a reason, when a field is out of range.
  bool isValid(std::string* error) const;
};

/// \brief Why `observations` and `params` cannot give a fit ("light fit: ..."), or nullopt when
/// they can: at least 5 observations not all on one line, with positive, finite radiance and
/// positive albedo, and valid params. A frame's references may fail it (an arm over them): the
/// pipeline asks this first and rejects the frame with the answer.
std::optional<std::string> lightFitProblem(std::span<const ReferenceObservation> observations,
                                           const LightFitParams& params = {});

/// \brief Fits the light's position (the monospectral mean of the channels drives the geometry,
/// with relative residuals, plus the weak prior) and then each channel's intensity (linear least
/// squares at that position). Throws CaptureError with lightFitProblem's answer when there is
/// one (ask it first where observations may be unusable). A fit that does not converge is
/// returned with converged = false.
LightFit fitPointLight(std::span<const ReferenceObservation> observations,
                       const LightFitParams& params = {});

}  // namespace slicecap::capture
