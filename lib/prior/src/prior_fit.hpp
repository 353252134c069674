// The prior's coefficients for a capture's samples: ridge fits chosen by generalised
// cross-validation, then one step to the true (linear-tap) measurement operator.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "prior_samples.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"

namespace slicecap::prior {

/// \brief The chosen fit: basis coefficients, then `termsUsed` half-vector term coefficients
/// (rows) x 3 channels, in the log domain of PriorModel (log(f cos cos + floor) - mean).
struct PriorFit {
  Eigen::MatrixXd coefficients;
  int termsUsed = 0;
  bool anisotropyTermsUsed = false;
  double isotropicScore = 0.0;
  double anisotropicScore = 0.0;  ///< 0 when not tried
  std::vector<ElevationPair> measuredPairs;
};

/// \brief Fits the model to the rows (`tapped` gathered from them; `floor` from logFloor). The
/// isotropic fit is the basis alone or with the isotropic hats, whichever scores lower; the
/// anisotropic terms are added when they cut the score below params.anisotropyScoreRatio of it.
PriorFit fitPrior(const SliceSet& slices, const std::vector<SampleRow>& rows,
                  const TappedEntries& tapped, const PriorModel& model, const PriorParams& params,
                  const Rgb& floor);

}  // namespace slicecap::prior
