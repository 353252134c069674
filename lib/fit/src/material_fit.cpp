// The fit: several starts per candidate model, the best converged one kept, the sheen term kept
// only when it lowers the error clearly.
#include "slicecap/fit/material_fit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "candidate_search.hpp"
#include "fit_data.hpp"
#include "parameter_conversion.hpp"
#include "slicecap/core/angles.hpp"
#include "start_solver.hpp"
#include "table_check.hpp"
#include "slicecap/fit/argument_error.hpp"

namespace slicecap::fit {
namespace {

using detail::FitData;
using detail::FitParameters;
using detail::SolveOutcome;
using detail::bestOf;
using detail::kScoutIterations;
using detail::kScoutStride;

// The start's lobe: elongated (3:1) so that each tangent start is a distinct basin.
constexpr double kStartAlphaTangent = 0.3, kStartAlphaBitangent = 0.1;
// Sheen starts: a pile dim against the diffuse on the GGX solution; and a pile with no specular at
// all (f0 = f90 = 0): a velvet's GGX fit bends its lobe to mimic the sheen, and from there the
// sheen term alone is a long way off. (A third start, a narrower pile on the GGX solution, changed
// no built-in material's result and cost a third more time.)
constexpr std::array<double, 1> kSheenStartRoughness{0.5};
constexpr double kSheenOnlyStartRoughness = 0.5;
// The sheen's start colour, a fraction of the GGX solution's brightest reflectance (albedo or f0):
// relative, so that a dark velvet starts as dim against its lobe as a bright one (an absolute 0.1
// lost the sheen of velvet-green-20 at a hundredth of its brightness: dE 1.15 -> 3.46).
constexpr double kSheenStartFraction = 0.17;

double percentile(std::vector<double> values, double fraction) {
  const auto k = static_cast<std::size_t>(fraction * double(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// A start at this tangent: the diffuse from the table's dim entries (a 20th percentile: the lobe
// covers fewer than 80 % of the pairs of any but the roughest material), f0 so that the start's
// lobe meets the table's brightest cos-weighted entry.
FitParameters ggxStart(const Abrdf& table, const FitData& data, double tangentDeg) {
  FitParameters p;
  std::array<std::vector<double>, 3> channels;
  for (int l = 0; l < Abrdf::kDirections; ++l)
    for (int v = 0; v < Abrdf::kDirections; ++v)
      for (int c = 0; c < 3; ++c) channels[static_cast<std::size_t>(c)].push_back(table.channel(l, v, c));
  for (std::size_t c = 0; c < 3; ++c) p.ggx[c] = std::numbers::pi * percentile(channels[c], 0.2);
  p.ggx[6] = std::log(kStartAlphaTangent);
  p.ggx[7] = std::log(kStartAlphaBitangent);
  p.ggx[8] = degToRad(tangentDeg);
  p.ggx[9] = 1.0;  // plain Schlick: what most measured materials show
  std::size_t brightest = 0;
  double brightestValue = -1.0;
  for (std::size_t i = 0; i < data.pairs.size(); ++i) {
    const double value = std::max({data.target[i][0], data.target[i][1], data.target[i][2]});
    if (value > brightestValue) brightestValue = value, brightest = i;
  }
  const double lobe = detail::ggxSpecular(data.pairs[brightest], kStartAlphaTangent,
                                          kStartAlphaBitangent, std::cos(p.ggx[8]),
                                          std::sin(p.ggx[8]));
  const int light = static_cast<int>(brightest) / Abrdf::kDirections;
  const int view = static_cast<int>(brightest) % Abrdf::kDirections;
  for (std::size_t c = 0; c < 3; ++c) {
    const double excess = table.channel(light, view, int(c)) - p.ggx[c] / std::numbers::pi;
    p.ggx[3 + c] = std::clamp(excess / lobe, 0.02, 1.0);
  }
  return p;
}

using detail::materialOf;

// How many of the most promising scouts are solved in full (candidate_search.hpp): two for
// the GGX (the tangent's basins), one for the sheen and the coat.
constexpr std::size_t kMaxPolishedGgx = 2, kMaxPolishedSheen = 1, kMaxPolishedCoat = 1;
// Coat starts: a sharp coat (a lacquer), a glossy one and a broad one, all at full weight.
constexpr std::array<double, 3> kCoatStartAlphas{0.03, 0.1, 0.3};
// How much broader the base lobe starts when the coat takes its place.
constexpr double kCoatSwapBroadening = 3.0;

std::string fixed2(double value) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(2);
  s << value;
  return s.str();
}

// The GGX candidate from one start per tangent; throws FitError naming the table when none of
// the starts converged.
CandidateFit fitGgx(const Abrdf& table, const std::string& name, const FitData& data,
                    const FitData& scoutData, const FitOptions& options) {
  std::vector<FitParameters> ggxStarts;
  for (double tangentDeg : options.startTangentsDeg)
    ggxStarts.push_back(ggxStart(table, data, tangentDeg));
  std::string failure;
  std::optional<CandidateFit> ggx =
      bestOf(table, data, scoutData, ggxStarts, options.maxIterations, kMaxPolishedGgx, failure);
  if (!ggx) {
    throw FitError(name + ": the GGX fit did not converge from any of " +
                   std::to_string(ggxStarts.size()) + " starts within " +
                   std::to_string(options.maxIterations) + " iterations (" + failure + ")");
  }
  return *ggx;
}

// A lobe whose alphas differ by less than this factor is taken as round: no isotropic solve.
constexpr double kRoundLobeRatio = 1.05;

// The rule a candidate with more parameters must meet to be chosen over the simpler one it
// extends (the sheen over GGX, the anisotropic lobe over the round one): its mean dE at most
// `maximumFraction` of the simpler one's and lower by at least `minimumGain`.
bool earnsItsParameters(double richerDeltaE, double simplerDeltaE, double maximumFraction,
                        double minimumGain) {
  return richerDeltaE <= maximumFraction * simplerDeltaE &&
         simplerDeltaE - richerDeltaE >= minimumGain;
}

// The rule in words, for `choice`: "needs dE <= 0.90 x SIMPLER's and a gain >= 0.10".
std::string ruleText(const std::string& simpler, double maximumFraction, double minimumGain) {
  return "needs dE <= " + fixed2(maximumFraction) + " x " + simpler + "'s and a gain >= " +
         fixed2(minimumGain);
}

// The isotropic candidate from the GGX solution (alphas at their geometric mean, tangent 0),
// appended to the candidates when it converged. Returns the index of the GGX candidate to keep
// (0, or the isotropic one when the anisotropic lobe does not earn its two parameters) and says
// why in `reason`.
std::size_t addIsotropicCandidate(const Abrdf& table, const FitData& data, const FitData& scoutData,
                                  const FitOptions& options, FitResult& result,
                                  std::string& reason) {
  // A copy: the push_back below may move the candidates, and a reference into them would dangle.
  const FittedMaterial m = result.candidates.front().material;
  const double alphaRatio = m.alphaTangent / m.alphaBitangent;
  if (alphaRatio <= kRoundLobeRatio) {
    reason = "the lobe is round (alpha ratio " + fixed2(alphaRatio) + ")";
    return 0;
  }
  FitParameters start = detail::ggxParametersOf(m);
  start.isotropic = true;
  start.ggx[6] = start.ggx[7] = 0.5 * (std::log(m.alphaTangent) + std::log(m.alphaBitangent));
  start.ggx[8] = 0.0;
  std::string failure;
  std::optional<CandidateFit> isotropic =
      bestOf(table, data, scoutData, {start}, options.maxIterations, kMaxPolishedGgx, failure);
  if (!isotropic) {
    reason = "anisotropic lobe (the isotropic fit did not converge: " + failure + ")";
    return 0;
  }
  result.candidates.push_back(*isotropic);
  const double anisotropicDeltaE = result.candidates.front().metrics.deltaE;
  const double isotropicDeltaE = isotropic->metrics.deltaE;
  const bool earns = earnsItsParameters(anisotropicDeltaE, isotropicDeltaE,
                                        options.anisotropyMaximumDeltaEFraction,
                                        options.anisotropyMinimumGainDeltaE);
  const std::string figures = "mean dE " + fixed2(isotropicDeltaE) + " (isotropic) -> " +
                              fixed2(anisotropicDeltaE) + " (anisotropic, alpha ratio " +
                              fixed2(alphaRatio) + "); " +
                              ruleText("isotropic", options.anisotropyMaximumDeltaEFraction,
                                       options.anisotropyMinimumGainDeltaE);
  if (earns) {
    reason = "anisotropic lobe: " + figures;
    return 0;
  }
  reason = "isotropic lobe: the anisotropy does not earn its 2 parameters, " + figures;
  return result.candidates.size() - 1;
}

// The sheen candidate's starts, all from the GGX solution `m`.
std::vector<FitParameters> sheenStartsFrom(const FittedMaterial& m, bool isotropic,
                                           SheenForm form) {
  // From the GGX solution (raw, not canonical: the same basin) plus a sheen term.
  std::vector<FitParameters> sheenStarts;
  double startColour =
      kSheenStartFraction * std::max(m.diffuseAlbedo.maxChannel(), m.specularF0.maxChannel());
  if (form == SheenForm::Khr) startColour = std::min(startColour, 1.0);  // the colour's bound
  for (double roughness : kSheenStartRoughness) {
    FitParameters p = detail::ggxParametersOf(m);
    p.withSheen = true;
    p.sheenForm = form;
    if (form == SheenForm::Khr)  // inside the khr form's alpha bound (start_solver.cpp)
      for (std::size_t i = 6; i < 8; ++i) p.ggx[i] = std::min(p.ggx[i], 0.0);
    p.isotropic = isotropic;
    p.sheen = {startColour, startColour, startColour, std::log(roughness)};
    sheenStarts.push_back(p);
  }
  // The GGX solution itself with no sheen yet: the sheen candidate then starts no worse than
  // the GGX fit (without it blue-plastic's sheen candidate settled at dE 4.15 against 3.47).
  FitParameters noSheenYet = sheenStarts.front();
  noSheenYet.sheen[0] = noSheenYet.sheen[1] = noSheenYet.sheen[2] = 0.0;
  FitParameters sheenOnly = sheenStarts.front();
  for (std::size_t c = 3; c < 6; ++c) sheenOnly.ggx[c] = 0.0;
  sheenOnly.ggx[9] = 0.0;
  sheenOnly.sheen[3] = std::log(kSheenOnlyStartRoughness);
  sheenStarts.push_back(sheenOnly);
  sheenStarts.push_back(noSheenYet);
  return sheenStarts;
}

// Fits ggx+sheen from the GGX candidate kept (result.candidates[ggx]) and appends it to the
// candidates when it converged. Returns whether the sheen term earns its parameters by the
// options' rule, i.e. whether the appended candidate is the chosen one; `reason` says why.
bool addSheenCandidate(const Abrdf& table, const FitData& data, const FitData& scoutData,
                       const FitOptions& options, std::size_t ggx, FitResult& result,
                       std::string& reason) {
  const double ggxDeltaE = result.candidates[ggx].metrics.deltaE;
  const std::vector<FitParameters> sheenStarts =
      sheenStartsFrom(result.candidates[ggx].material, result.candidates[ggx].isotropicLobe,
                      options.sheenForm);
  std::string sheenFailure;
  std::optional<CandidateFit> sheen = bestOf(table, data, scoutData, sheenStarts,
                                             options.maxIterations, kMaxPolishedSheen, sheenFailure);
  if (!sheen) {
    reason = "the ggx+sheen fit did not converge (" + sheenFailure + ")";
    return false;
  }
  result.candidates.push_back(*sheen);
  const double sheenDeltaE = sheen->metrics.deltaE;
  const bool earns = earnsItsParameters(sheenDeltaE, ggxDeltaE, options.sheenMaximumDeltaEFraction,
                                        options.sheenMinimumGainDeltaE);
  const std::string figures = "mean dE " + fixed2(ggxDeltaE) + " (ggx) -> " +
                              fixed2(sheenDeltaE) + " (ggx+sheen)";
  const std::string rule =
      ruleText("ggx", options.sheenMaximumDeltaEFraction, options.sheenMinimumGainDeltaE);
  reason = earns ? "the sheen term lowers " + figures + "; " + rule
                 : "the sheen term does not earn its 4 parameters, " + figures + "; " + rule;
  return earns;
}

// The coat's starts, from the candidate `base` (its sheen too): a sharp, a glossy and a broad coat
// at full weight over the base as fitted; the base itself with no coat yet (the coat candidate then
// starts no worse than the base); and the roles swapped: the coat takes the base's lobe, and the
// base gets a new one, the lobe broadened 3x and, because the one-lobe fit has not seen the base's
// anisotropy, an elongated lobe at each tangent start. Why the swap: over a faint rough lobe (a
// lacquered dielectric) the one-lobe fit spends its lobe on the coat's sharp highlight, and from
// there a coat start settles with the coat as the rough lobe and the sharp one left in the base
// (a lacquered red: dE 0.33 instead of 0); and a brushed base under a coat came out round (dE 0.89
// for alphas 0.45 / 0.2 under a coat of alpha 0.05) or with no coat at all (dE 1.60, 0.6 / 0.1).
std::vector<FitParameters> coatStartsFrom(const CandidateFit& base,
                                          const std::vector<double>& startTangentsDeg) {
  const FittedMaterial& m = base.material;
  FitParameters p = detail::ggxParametersOf(m);
  p.isotropic = base.isotropicLobe;
  p.withSheen = hasSheen(m.model);
  if (p.withSheen)
    p.sheen = {m.sheenColour[0], m.sheenColour[1], m.sheenColour[2], std::log(m.sheenRoughness)};
  p.withCoat = true;
  std::vector<FitParameters> starts;
  for (double alpha : kCoatStartAlphas) {
    p.coat = {1.0, std::log(alpha)};
    starts.push_back(p);
  }
  FitParameters noCoatYet = p;
  noCoatYet.coat = {0.0, std::log(kCoatStartAlphas[1])};
  starts.push_back(noCoatYet);
  // The swap: a coat whose weight gives the lobe's reflectance face on, as far as a coat of F0 0.04
  // reaches; the base's colours kept.
  const double lobeAlpha = std::sqrt(m.alphaTangent * m.alphaBitangent);
  p.coat = {std::clamp(m.specularF0.maxChannel() / kCoatF0, 0.05, 1.0), std::log(lobeAlpha)};
  FitParameters broadened = p;
  broadened.ggx[6] = std::log(std::min(m.alphaTangent * kCoatSwapBroadening, 1.0));
  broadened.ggx[7] = std::log(std::min(m.alphaBitangent * kCoatSwapBroadening, 1.0));
  starts.push_back(broadened);
  for (double tangentDeg : startTangentsDeg) {
    FitParameters elongated = p;
    elongated.isotropic = false;
    elongated.ggx[6] = std::log(kStartAlphaTangent);
    elongated.ggx[7] = std::log(kStartAlphaBitangent);
    elongated.ggx[8] = degToRad(tangentDeg);
    starts.push_back(elongated);
  }
  return starts;
}

// Fits the coat on top of the candidate chosen so far (result.candidates[base]) and appends it
// when it converged. Returns whether the coat earns its 2 parameters; `reason` says why.
bool addCoatCandidate(const Abrdf& table, const FitData& data, const FitData& scoutData,
                      const FitOptions& options, std::size_t base, FitResult& result,
                      std::string& reason) {
  const CandidateFit& baseFit = result.candidates[base];
  const double baseDeltaE = baseFit.metrics.deltaE;
  const std::string baseName(toString(baseFit.model));
  const bool baseIsotropic = baseFit.isotropicLobe;
  if (baseDeltaE < options.coatMinimumGainDeltaE) {
    reason = "coat not tried (dE " + fixed2(baseDeltaE) + " is below the gain of " +
             fixed2(options.coatMinimumGainDeltaE) + " it would have to bring)";
    return false;
  }
  std::string failure;
  // The elongated base lobe of the swapped starts: along the free GGX fit's tangent when that lobe
  // is elongated (its direction is seen), else at every tangent start.
  const FittedMaterial& freeLobe = result.candidates.front().material;
  const std::vector<double> swapTangentsDeg =
      freeLobe.alphaTangent > kRoundLobeRatio * freeLobe.alphaBitangent
          ? std::vector<double>{freeLobe.tangentDeg}
          : options.startTangentsDeg;
  const std::vector<detail::Scout> scouts = detail::scoutStarts(
      scoutData, coatStartsFrom(baseFit, swapTangentsDeg), options.maxIterations);
  // Every start's coat faded away while scouting: the full solve would end at the base without a
  // coat, so it is not run.
  if (!scouts.empty() && scouts.front().outcome.parameters.coat[0] <= 0.0) {
    reason = "no coat: the best of the coat's starts has weight 0 after " +
             std::to_string(kScoutIterations) + " iterations on a third of the pairs";
    return false;
  }
  std::optional<CandidateFit> coat = detail::polishBest(table, data, scouts, options.maxIterations,
                                                       kMaxPolishedCoat, failure);
  if (!coat) {
    reason = "the " + baseName + "+coat fit did not converge (" + failure + ")";
    return false;
  }
  result.candidates.push_back(*coat);  // baseFit may dangle from here on
  const double coatDeltaE = coat->metrics.deltaE;
  // A swapped start may free the lobe of an isotropic base: then, if the lobe came out elongated,
  // the coat brings 4 parameters.
  const FittedMaterial& coated = coat->material;
  const bool freedLobe = baseIsotropic && !coat->isotropicLobe &&
                         coated.alphaTangent > kRoundLobeRatio * coated.alphaBitangent;
  const bool earns = earnsItsParameters(coatDeltaE, baseDeltaE, options.coatMaximumDeltaEFraction,
                                        options.coatMinimumGainDeltaE);
  const std::string figures = "mean dE " + fixed2(baseDeltaE) + " (" + baseName + ") -> " +
                              fixed2(coatDeltaE) + " (" + std::string(toString(coat->model)) +
                              ", weight " + fixed2(coat->material.coatWeight) + ", alpha " +
                              fixed2(coat->material.coatAlpha) +
                              (freedLobe ? ", its lobe anisotropic" : "") + "); " +
                              ruleText(baseName, options.coatMaximumDeltaEFraction,
                                       options.coatMinimumGainDeltaE);
  reason = earns ? "the coat lowers " + figures
                 : std::string("the coat does not earn its ") + (freedLobe ? "4" : "2") +
                       " parameters, " + figures;
  return earns;
}

}  // namespace

FitResult fitMaterial(const Abrdf& table, const std::string& name, const FitOptions& options) {
  detail::requireBrdf(table, name);
  if (options.startTangentsDeg.empty() || options.maxIterations < 1)
    throw FitArgumentError("fitMaterial: needs at least one start and one iteration");
  const FitData data = detail::makeFitData(table);
  const FitData scoutData = detail::everyNthPair(data, kScoutStride);

  FitResult result;
  result.candidates.push_back(fitGgx(table, name, data, scoutData, options));
  // Indices, not pointers: appending a candidate may move the vector's elements.
  std::string lobeReason = "anisotropic lobe (isotropic not tried)";
  const std::size_t ggx =
      options.tryIsotropic
          ? addIsotropicCandidate(table, data, scoutData, options, result, lobeReason)
          : 0;
  std::size_t chosen = ggx;
  std::string sheenReason = "sheen not tried";

  const double ggxDeltaE = result.candidates[ggx].metrics.deltaE;
  if (options.trySheen && ggxDeltaE < options.sheenMinimumGainDeltaE) {
    // The rule could not choose the sheen: skip its solves (most of the fit's time).
    sheenReason = "its mean dE " + fixed2(ggxDeltaE) + " is already below the gain of " +
                  fixed2(options.sheenMinimumGainDeltaE) +
                  " a sheen term would have to bring; ggx+sheen not tried";
  } else if (options.trySheen &&
             addSheenCandidate(table, data, scoutData, options, ggx, result, sheenReason)) {
    chosen = result.candidates.size() - 1;
  }
  std::string coatReason = "coat not tried";
  if (options.tryCoat && addCoatCandidate(table, data, scoutData, options, chosen, result, coatReason))
    chosen = result.candidates.size() - 1;
  result.choiceReason = std::string(toString(result.candidates[chosen].model)) + ": " +
                        sheenReason + "; " + coatReason + "; " + lobeReason;
  // Every candidate says the form its sheen (or a sheen added to it) takes: the JSON's one
  // "sheen_form" holds for them all.
  for (CandidateFit& c : result.candidates) c.material.sheenForm = options.sheenForm;
  const CandidateFit& chosenFit = result.candidates[chosen];
  result.material = chosenFit.material;
  result.sigmas = chosenFit.sigmas;
  result.metrics = chosenFit.metrics;
  return result;
}

}  // namespace slicecap::fit
