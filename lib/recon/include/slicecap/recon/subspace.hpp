// One (theta_i, theta_v) block of the table, on its own ring azimuths (docs/method.md §1.3), and its
// resampling.
#pragma once

#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::recon {

/// \brief S[p][q] = A[ring(theta_i)[p], ring(theta_v)[q]]: p indexes phi_i, q indexes phi_v.
class Subspace {
 public:
  /// \brief A zero block; throws slicecap::CoreError when an elevation is not a Bonn ring.
  explicit Subspace(ElevationPair elevations);

  /// \brief The block of a full table.
  static Subspace fromTable(const Abrdf& table, ElevationPair elevations);
  /// \brief Writes this block into its place in a full table.
  void writeTo(Abrdf& table) const;

  ElevationPair elevations() const { return elevations_; }
  const Ring& lightRing() const { return *lightRing_; }
  const Ring& viewRing() const { return *viewRing_; }

  Rgb& at(int lightAzimuthIndex, int viewAzimuthIndex) {
    return values_[lightAzimuthIndex * viewRing_->count + viewAzimuthIndex];
  }
  const Rgb& at(int lightAzimuthIndex, int viewAzimuthIndex) const {
    return values_[lightAzimuthIndex * viewRing_->count + viewAzimuthIndex];
  }

  /// \brief This block moved to another view elevation: each row resampled along phi_v by periodic
  /// linear interpolation (to the pole: the average over phi_v). Values are not scaled.
  Subspace resampledToViewElevation(int thetaVDeg) const;
  /// \brief Likewise along phi_i, to another light elevation.
  Subspace resampledToLightElevation(int thetaIDeg) const;

  /// \brief (1 - t) low + t high of two blocks of one light elevation, each first resampled to
  /// `thetaVDeg` as resampledToViewElevation does: blend(low', high', t) in one pass, without the
  /// two resampled blocks (this is most of the work of an elevation interpolation). Throws
  /// ReconArgumentError when the two light elevations differ.
  static Subspace blendAtViewElevation(const Subspace& low, const Subspace& high, double t,
                                       int thetaVDeg);
  /// \brief Likewise of two blocks of one view elevation, resampled to `thetaIDeg` along phi_i.
  static Subspace blendAtLightElevation(const Subspace& low, const Subspace& high, double t,
                                        int thetaIDeg);

  /// \brief Every value multiplied by `factor`.
  Subspace& scale(double factor);
  /// \brief (1 - t) a + t b of two blocks of the same shape; throws ReconArgumentError
  /// otherwise.
  static Subspace blend(const Subspace& a, const Subspace& b, double t);

 private:
  ElevationPair elevations_;
  const Ring* lightRing_;
  const Ring* viewRing_;
  std::vector<Rgb> values_;
};

/// \brief Values of a ring resampled to another ring's azimuths (periodic linear; to a ring of one:
/// the mean). Exposed for tests and for other resampling needs.
std::vector<Rgb> resampleRing(const std::vector<Rgb>& values, const Ring& to);

}  // namespace slicecap::recon
