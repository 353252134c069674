// Reconstruction with the learned prior: a fit at the samples' actual angles, anisotropy through
// the half vector, the measured slices kept.
#pragma once

#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {

/// \brief Options of the prior reconstruction; the defaults were chosen by 5-fold cross-validation
/// within the 100 MERL tables (docs/results/2026-11-24-prior.md).
struct PriorParams {
  /// \brief Ridge weight: component k is penalised by ridge * residualVariance / variance_k.
  double ridge = 30.0;
  /// \brief The ridge weight when the slices measure at most two elevation pairs (the two
  /// diagonal sweeps 30/30 and 75/75 an operator of an isotropic material may stop at). Chosen
  /// like `ridge`, by 5-fold cross-validation within MERL for that capture, ideal and noisy
  /// averaged (mean dE at 3 / 9 / 30: 1.22 and 1.81 / 1.41 and 1.57 / 1.88 and 1.67): with 4 or 8
  /// pairs 30 stays best (9 gives 0.81 vs 0.79 ideal, 1.15 vs 1.10 noisy).
  double fewPairsRidge = 9.0;
  /// \brief Penalty of each half-vector anisotropy term (log domain).
  double anisotropyRidge = 0.1;
  /// \brief The anisotropy terms are used when they cut the generalised cross-validation score of
  /// the fit below this fraction of the isotropic fit's (no MERL table went below 0.48).
  double anisotropyScoreRatio = 0.3;
  /// \brief Never use the anisotropy terms (e.g. an operator who knows the material is isotropic).
  bool isotropicOnly = false;
  /// \brief How a sample's design row is read. True (a capture): at the sample's own measured
  /// angles -- the learned basis and mean, which are isotropic, at its own phi_v - phi_i and
  /// elevations (the sample turned about the normal so that one direction sits on a grid
  /// azimuth), the half-vector terms at its own directions; the error then does not depend on
  /// where the samples fall inside their bins. False: through the table's linear interpolation at
  /// the sample's angles (tableTaps), which is exact only when the truth between grid azimuths IS
  /// that interpolation (slices extracted from a table, docs/method.md §2.3); read that way, a real
  /// capture's samples between grid azimuths blend entries a bin apart and smear highlights.
  bool readAtMeasuredAngles = true;
  /// \brief Blend with Method B where the samples show little directional structure: near-diffuse
  /// materials (felts, papers, matte paints, spectralon), where B's one-lobe model is nearly exact
  /// and a basis learned mostly from glossy tables adds structure that is not there. The weight
  /// of the prior, in the log domain, rises linearly with the samples' dynamic range (natural log
  /// of the largest cos-weighted sample over the median) from 0 at blendFromLog to 1 at
  /// blendToLog. Needs the slices Method B needs (all eight, or the four diagonal ones);
  /// otherwise the prior stands alone. The range was chosen by 5-fold cross-validation within the
  /// 100 MERL tables, ideal and noisy captures together (docs/results/2026-11-24-prior.md).
  bool blendWithMethodB = true;
  double blendFromLog = 0.45;
  double blendToLog = 2.45;
  /// \brief Fit every window cell of a capture as a point of its own (Slice::cellFrames, where a
  /// slice has them) instead of one sample per bin; the slices' samples still give the residuals
  /// kept, the dynamic range and the blend with Method B. The cells of one frame share its pose,
  /// exposure and irradiance fit, and the basis's error over the few degrees the window spans,
  /// so they are one group (docs/method.md §9.4, "The prior on every cell"): with
  /// frameAsOneSample (the default) each frame's cells share the weight of one sample, cell i of
  /// frame g weighing w_i / sum_g w, w_i = cellOwnLogSigma^2 / (cellOwnLogSigma^2 + v_i) and v_i
  /// its noise in the log domain; otherwise generalised least squares with a random frame effect
  /// of sigma frameCommonLogSigma (frame_groups.hpp), which weighs the differences between one
  /// frame's cells far more and did worse (satin-blue-45: dE 4.59 against 2.85). A sample outside
  /// any frame group counts as it does without cells.
  bool fitEveryCell = false;
  double cellOwnLogSigma = 0.05;
  double frameCommonLogSigma = 0.05;
  bool frameAsOneSample = true;
  /// \brief Returns false, with a reason, when a field is out of range.
  bool isValid(std::string* error) const;
};

/// \brief What the reconstruction did, for the CLI and tests.
struct PriorReport {
  std::size_t samples = 0;         ///< the points fitted (every cell with fitEveryCell)
  std::size_t frameGroups = 0;     ///< the frames whose cells were fitted as a group
  std::vector<ElevationPair> measuredPairs;
  bool anisotropyTermsUsed = false;
  double isotropicScore = 0.0;    ///< GCV score of the isotropic fit (log domain)
  double anisotropicScore = 0.0;  ///< the same with the half-vector terms (0 when not tried)
  double fitRmsLog = 0.0;         ///< RMS of the samples' log residuals before they are kept
  double dynamicRangeLog = 0.0;   ///< log(largest / median cos-weighted sample), see PriorParams
  double priorWeight = 1.0;       ///< the prior's weight in the blend with Method B (1: alone)
  bool methodBBlended = false;    ///< Method B ran and was blended in (priorWeight < 1)
};

/// \brief The 81 x 81 table from any slices: every sample counts at its actual light and view
/// directions (tableTaps), so jittered, missing, extra and partial slices are fine. Throws
/// recon::ReconstructionError when there are no samples or a sample lies off the hemisphere
/// (naming its slice), PriorError for invalid params. Negative results are clipped to 0.
Abrdf reconstructWithPrior(const SliceSet& slices, const PriorModel& model,
                           const PriorParams& params = {}, PriorReport* report = nullptr);

/// \brief reconstructWithPrior for many reconstructions with one model and one set of params (a
/// BTF's texels), with the same results to the bit. It keeps a copy of the model's basis entry by
/// entry (PriorModel::basis is stored component by component): a texel's samples lie off the
/// grid and read 16 table entries each, and gathering an entry's components then reads one cache
/// line instead of one per component. Built in about a millisecond (420 kB for 16 components);
/// the model must outlive it. `reconstruct` is const and may run on many threads at once.
class PriorReconstructor {
 public:
  /// \brief Throws PriorError for invalid params or a basis of the wrong size.
  explicit PriorReconstructor(const PriorModel& model, const PriorParams& params = {});
  /// \brief As reconstructWithPrior(slices, model, params, report).
  Abrdf reconstruct(const SliceSet& slices, PriorReport* report = nullptr) const;

 private:
  const PriorModel* model_;
  PriorParams params_;
  std::vector<float> basisByEntry_;  // kFeatureCount x components
};

}  // namespace slicecap::prior
