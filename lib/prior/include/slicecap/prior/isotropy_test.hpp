// The isotropy test: do the diagonal sweeps (and axial ones, if any) look like an isotropic
// material? Decides whether the axial sweeps are needed.
#pragma once

#include <string>
#include <vector>

#include "slicecap/core/slice.hpp"

namespace slicecap::prior {

/// \brief Options of the test; thresholds were set on the 100 MERL tables under capture noise
/// (README "Isotropy test").
struct IsotropyParams {
  /// \brief Values below this fraction of the largest cos(theta_i)-weighted sample are raised to
  /// it before logarithms (what 8-bit output cannot show cannot count as anisotropy).
  double floorFraction = 0.01;
  /// \brief Largest RMS log asymmetry of a diagonal slice an isotropic material may show.
  double diagonalThreshold = 0.15;
  /// \brief Largest RMS log spread of an axial slice an isotropic material may show.
  double axialThreshold = 0.15;
  bool isValid(std::string* error) const;
};

/// \brief The score of one slice.
struct SliceIsotropyScore {
  SliceId slice;
  double score = 0.0;       ///< RMS log deviation from what an isotropic material would show
  bool informative = true;  ///< false for checks that cannot see anisotropy (explained in README)
};

/// \brief The verdict and its evidence.
struct IsotropyVerdict {
  bool isotropic = true;
  double diagonalScore = 0.0;  ///< largest diagonal-slice score
  double axialScore = 0.0;     ///< largest axial-slice score (0 without axial slices)
  std::vector<SliceIsotropyScore> slices;
  std::string reason;  ///< one sentence for the operator
};

/// \brief An isotropic material's diagonal slice s(x) (phi_i = -phi_v = -x) depends on
/// phi_v - phi_i = 2x only through its cosine: s(x) = s(x + 180) (half turn) and s(x) = s(-x)
/// (mirror); its axial slice is constant. Each diagonal slice is scored by the RMS log difference
/// of its samples to their half-turn and mirror partners (read by periodic linear interpolation);
/// each axial slice by the RMS log spread about its mean. Throws std::invalid_argument when the
/// set has no diagonal and no axial slice with two or more samples, or for invalid params.
IsotropyVerdict testIsotropy(const SliceSet& slices, const IsotropyParams& params = {});

}  // namespace slicecap::prior
