// The isotropy test: do the diagonal sweeps (and axial ones, if any) look like an isotropic
// material? Decides whether the axial sweeps are needed.
#pragma once

#include <string>
#include <vector>

#include "slicecap/core/slice.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {

/// \brief Options of the test; thresholds were set on the 100 MERL tables, ideal and under capture
/// noise (docs/method.md §8.1).
struct IsotropyParams {
  /// \brief Values below this fraction of the largest cos(theta_i)-weighted sample are raised to
  /// it before logarithms (what 8-bit output cannot show cannot count as anisotropy).
  double floorFraction = 0.01;
  /// \brief Largest RMS log asymmetry of a diagonal slice an isotropic material may show. With
  /// +-3 deg angle jitter isotropic MERL tables reach 1.5 (highlights move), so by default only a
  /// gross asymmetry counts; the prior's test below is what sees the usual anisotropy.
  double diagonalThreshold = 2.0;
  /// \brief Largest RMS log spread of an axial slice an isotropic material may show (MERL under
  /// capture noise: at most 0.13).
  double axialThreshold = 0.2;
  /// \brief With a prior: anisotropic when the half-vector anisotropy terms cut the fit's
  /// generalised cross-validation score below this fraction of the isotropic fit's (as
  /// PriorParams::anisotropyScoreRatio).
  double priorScoreRatio = 0.3;
  /// \brief PriorParams::readAtMeasuredAngles of the prior's fit. Off by default: priorScoreRatio
  /// was set with the table's interpolation, and reading the basis at the samples' own relative
  /// azimuth changes the scores of slices extracted from a table (blue-plastic's ratio falls to
  /// 0.28); it has not been set again for captures.
  bool readAtMeasuredAngles = false;
  bool isValid(std::string* error) const;
};

/// \brief The score of one slice.
struct SliceIsotropyScore {
  SliceId slice;
  double score = 0.0;       ///< RMS log deviation from what an isotropic material would show
  bool informative = true;  ///< false for checks that cannot see anisotropy (docs/method.md §8.1)
};

/// \brief The verdict and its evidence.
struct IsotropyVerdict {
  bool isotropic = true;
  double diagonalScore = 0.0;  ///< largest diagonal-slice score
  double axialScore = 0.0;     ///< largest axial-slice score (0 without axial slices)
  /// \brief GCV score of the prior fit with anisotropy terms over the isotropic one's (1 without a
  /// prior or when the slices cannot show anisotropy to it).
  double priorScoreRatio = 1.0;
  /// \brief false when no slice can show anisotropy (only equal-elevation diagonal slices: there
  /// reciprocity and central symmetry hide it); the verdict is then "isotropic" by default.
  bool informative = true;
  std::vector<SliceIsotropyScore> slices;
  std::string reason;  ///< one sentence for the operator
};

/// \brief An isotropic material's diagonal slice s(x) (phi_i = -phi_v = -x) depends on
/// phi_v - phi_i = 2x only through its cosine: s(x) = s(x + 180) (half turn) and s(x) = s(-x)
/// (mirror); its axial slice is constant. Each diagonal slice is scored by the RMS log difference
/// of its samples to their half-turn and mirror partners (read by periodic linear interpolation);
/// each axial slice by the RMS log spread about its mean. Throws PriorError when the
/// set has no diagonal and no axial slice with two or more samples, or for invalid params.
IsotropyVerdict testIsotropy(const SliceSet& slices, const IsotropyParams& params = {});

/// \brief The symmetry test plus the prior's: the slices are fitted by reconstructWithPrior at
/// their actual angles with and without half-vector anisotropy terms, and the material is
/// anisotropic when the terms explain the samples far better (priorScoreRatio). Being a fit at the
/// actual angles, it is not fooled by angle jitter, and it sees a grain along phi = 0 or 90 deg
/// through the mixed-elevation diagonal slices. Errors as the other overload and
/// reconstructWithPrior.
IsotropyVerdict testIsotropy(const SliceSet& slices, const PriorModel& model,
                             const IsotropyParams& params = {});

}  // namespace slicecap::prior
