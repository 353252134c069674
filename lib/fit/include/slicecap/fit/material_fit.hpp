// Fitting a FittedMaterial to a measured 81 x 81 table (issue 30 item 1).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/error.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::fit {

/// \brief A table that cannot be fitted (not a BRDF) or a fit that did not converge; what() starts
/// with the table's name (its path for the command line).
class FitError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

struct FitOptions {
  /// \brief Tangent angles the solver starts from, deg (each with an elongated 0.3 x 0.1 lobe).
  /// The cost is multimodal in the tangent: a start far from the true tangent can settle in a
  /// local minimum, so starts spread over the half turn the lobe repeats in, and the best wins.
  std::vector<double> startTangentsDeg{0.0, 45.0, 90.0, 135.0};
  int maxIterations = 200;     ///< Levenberg-Marquardt iterations per solve
  bool trySheen = true;        ///< also fit GGX + sheen and keep it if it earns its place
  /// \brief The sheen model is chosen only when its mean dE is at most this fraction of the GGX
  /// fit's and lower by at least `sheenMinimumGainDeltaE` (both: a tenth of a dE on a nearly
  /// perfect fit is not worth four more parameters).
  double sheenMaximumDeltaEFraction = 0.9;
  double sheenMinimumGainDeltaE = 0.1;
  /// \brief The form the sheen candidate is fitted in: KHR_materials_sheen's layering (what a
  /// glTF viewer renders, format version 2's default), or version 1's additive form (kept to
  /// compare the two and to refit a version-1 material as it was).
  SheenForm sheenForm = SheenForm::Khr;
  /// \brief Also fit the lobe isotropic (one alpha, no tangent) when the GGX fit's lobe is not
  /// round, and keep the anisotropic lobe only when it earns its two parameters by the rule below
  /// (as the sheen's). Why: a lobe narrower than the grid's 15 deg steps is seen at the mirror
  /// pairs only, where D depends on alpha_t alpha_b alone; the fit of an isotropic glossy table
  /// then settles on any elongation (measured plastics and metals: ratios up to 85 for a dE
  /// change of thousandths), which a renderer shows as a streak the material does not have.
  ///
  /// The rule is the absolute gain alone (fraction 1): the stretched fits differ from the round
  /// ones by hundredths (at most 0.04 on the measured tables), while a capture's reconstruction,
  /// fitted at dE 4-5, can gain 0.4 from a real anisotropy (ratio 2.4) that a 10 % bar would drop
  /// (satin-blue-45 from the prior, docs/results/2026-12-02-fit-of-captures.md, 2026-12-03).
  bool tryIsotropic = true;
  double anisotropyMaximumDeltaEFraction = 1.0;
  double anisotropyMinimumGainDeltaE = 0.1;
  /// \brief Also fit a clear coat on top of the model chosen so far (GGX or GGX + sheen) and keep
  /// it by the same rule: a lacquer, a varnish, a glazed print have a sharp reflection of the coat
  /// above a rougher base that one GGX lobe cannot hold.
  bool tryCoat = true;
  double coatMaximumDeltaEFraction = 0.9;
  double coatMinimumGainDeltaE = 0.1;
};

/// \brief One standard deviation of each parameter, in the parameter's own unit, from the
/// Jacobian at the solution: cov = s^2 (J^T J)^-1 with s^2 the residual variance. Formal: it
/// treats the misfit as noise. nullopt where the data do not determine the parameter (e.g. the
/// tangent of an isotropic lobe).
struct ParameterSigmas {
  std::array<std::optional<double>, 3> diffuseAlbedo, specularF0, sheenColour;
  std::optional<double> specularF90, alphaTangent, alphaBitangent, tangentDeg, sheenRoughness;
  std::optional<double> coatWeight, coatAlpha;
};

/// \brief How one candidate model fitted.
struct CandidateFit {
  MaterialModel model = MaterialModel::Ggx;
  FittedMaterial material;
  ParameterSigmas sigmas;
  eval::Metrics metrics;     ///< of tabulate(material) against the table
  double cost = 0.0;         ///< 1/2 sum of squared residuals (8-bit sRGB levels)
  int iterations = 0;        ///< of the best start, summed over its solves
  int startsTried = 0;       ///< starts scouted
  int solvesConverged = 0;   ///< full solves (of the most promising starts) that converged
  double bestStartTangentDeg = 0.0;  ///< the start the kept solution came from
  bool isotropicLobe = false;  ///< solved with alpha_t = alpha_b and no tangent
};

struct FitResult {
  FittedMaterial material;  ///< the chosen candidate's material (canonical)
  ParameterSigmas sigmas;
  eval::Metrics metrics;
  /// \brief ggx first, then the isotropic ggx when tried, then ggx+sheen when tried (from the
  /// ggx candidate kept, with its lobe's isotropy), then the coat on the model chosen so far when
  /// tried.
  std::vector<CandidateFit> candidates;
  std::string choiceReason;              ///< why this model, in a sentence
};

/// \brief Fits the table. `name` (the file's path) starts every error message.
///
/// Residuals: per light/view pair and channel, 255 (g(f cos_i / M) - g(t cos_i / M)) with g the
/// sRGB curve (continued past 1), f the model, t the table and M the table's largest cos-weighted
/// value: the paper's 8-bit convention of eval::compare without the rounding, so highlights and
/// diffuse both count and the least-squares optimum is where the reported RMSE is. Each start is
/// a bounded Levenberg-Marquardt solve (Ceres, dense, one thread, automatic derivatives).
///
/// Throws FitError naming `name` when the table holds a negative or non-finite value or no
/// positive one (not a BRDF), or when no full GGX solve converged within maxIterations (a sheen or
/// coat candidate that does not converge is only left out, and choiceReason says so);
/// FitArgumentError for options with no start or fewer than one iteration.
FitResult fitMaterial(const Abrdf& table, const std::string& name, const FitOptions& options = {});

}  // namespace slicecap::fit
