// The one-lobe Lafortune model of Method B along one elevation line, fitted with Ceres (eq. 6).
#pragma once

#include <span>
#include <string>

namespace slicecap::recon {

/// \brief A monospectral value at an elevation along a line where only that elevation varies.
struct ElevationSample {
  double thetaDeg = 0.0;
  double value = 0.0;
};

/// \brief mu(theta) = k cos^n(theta): eq. 6 with the fixed elevation folded into k.
struct ElevationLobe {
  double k = 1.0;
  double n = 0.0;
  /// \brief k cos^n(theta), the model's mean at an elevation below 90 deg.
  double operator()(double thetaDeg) const;
  /// \brief cos^n(theta): the model without its scale (k cancels in Method B's weights).
  double shape(double thetaDeg) const;
};

/// \brief What the fit did, for reports and for the convergence check.
struct LobeFitResult {
  ElevationLobe lobe;
  bool converged =
      false;  ///< Ceres stopped on a tolerance (not the iteration limit), finite result
  int iterations = 0;
  double finalCost = 0.0;  ///< half the sum of squared residuals relative to their group mean
  std::string message;     ///< why Ceres stopped
};

/// \brief Options of the fit; the defaults are the paper's constant start (k = 1 on the data's own
/// scale, n = 1).
struct LobeFitParams {
  double initialN = 1.0;
  int maxIterations = 100;
  /// \brief Values are clamped to at least this before fitting (docs/method.md §4.2), in data units.
  double minimumValue = 1e-6;
  /// \brief Returns false, with a reason, when a field is out of range.
  bool isValid(std::string* error) const;
};

/// \brief Least squares of k cos^n(theta) over the samples, each relative to the mean at its
/// elevation (LobeCost), by Ceres' TinySolver (Levenberg-Marquardt
/// from the paper's constant start: k = the samples' mean, n = initialN). Needs samples at two or
/// more distinct elevations below 90 deg
/// Needs samples at two or more distinct elevations below 90 deg; throws ReconArgumentError
/// otherwise or for non-finite input. A non-converged fit is returned with converged = false.
LobeFitResult fitElevationLobe(std::span<const ElevationSample> samples,
                               const LobeFitParams& params = {});

/// \brief The exact least-squares curve through the means of two elevation groups (docs/method.md §4.2),
/// the reference the Ceres fit is checked against.
ElevationLobe closedFormLobe(double theta1Deg, double mean1, double theta2Deg, double mean2,
                             double minimumValue = 1e-6);

}  // namespace slicecap::recon
