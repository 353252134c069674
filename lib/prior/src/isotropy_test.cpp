// The isotropy test on slice samples: half-turn and mirror symmetry of diagonal slices, flatness of
// axial ones.
#include "slicecap/prior/isotropy_test.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "slicecap/core/angles.hpp"
#include "slicecap/prior/prior_model.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/periodic_signal.hpp"

namespace slicecap::prior {
namespace {

// The monospectral log value of a sample, as the paper's metric sees it (times cos theta_i).
double logValue(const SliceSample& s, double floor) {
  return std::log(
      std::max(0.0, s.value.mean()) * std::cos(degToRad(std::min(s.light.thetaDeg, 90.0))) + floor);
}

// The log floor: a fraction of the largest sample, so that zeros and dark samples do not dominate.
double logFloor(const SliceSet& slices, const IsotropyParams& params) {
  double largest = 0.0;
  for (const Slice& slice : slices.slices()) {
    for (const SliceSample& s : slice.samples)
      largest = std::max(largest, std::exp(logValue(s, 0.0)));
  }
  return std::max(params.floorFraction * largest, 1e-30);
}

// A sum of squared log differences and how many terms it has.
struct SquaredTerms {
  double squares = 0.0;
  int terms = 0;
};

// An axial slice should be flat: its spread about the mean.
SquaredTerms axialSpread(const recon::PeriodicSignal& signal) {
  SquaredTerms sum;
  double mean = 0.0;
  for (const auto& p : signal.points())
    mean += p.value[0];
  mean /= double(signal.points().size());
  for (const auto& p : signal.points()) {
    sum.squares += (p.value[0] - mean) * (p.value[0] - mean);
    ++sum.terms;
  }
  return sum;
}

// A diagonal slice's half-turn asymmetry, and its mirror asymmetry when that is informative.
SquaredTerms diagonalAsymmetry(const recon::PeriodicSignal& signal, bool mirrorInformative) {
  SquaredTerms sum;
  for (const auto& p : signal.points()) {
    const double halfTurn = p.value[0] - signal.at(p.positionDeg + 180.0)[0];
    sum.squares += halfTurn * halfTurn;
    ++sum.terms;
    if (mirrorInformative) {
      const double mirror = p.value[0] - signal.at(360.0 - p.positionDeg)[0];
      sum.squares += mirror * mirror;
      ++sum.terms;
    }
  }
  return sum;
}

// The RMS log score of one slice of two or more samples.
SliceIsotropyScore scoreSlice(const Slice& slice, double floor) {
  std::vector<recon::SignalPoint> points;
  for (const SliceSample& s : slice.samples)
    points.push_back({sliceParameterDeg(slice.id.kind, s), Rgb::gray(logValue(s, floor))});
  const recon::PeriodicSignal signal(points);
  SliceIsotropyScore score{slice.id, 0.0, true};
  SquaredTerms sum;
  if (slice.id.kind == SliceKind::Axial) {
    sum = axialSpread(signal);
  } else {
    // At equal elevations reciprocity alone makes s(x) = s(-x), so only mixed pairs test it;
    // the half-turn sees only surfaces without central symmetry (no microfacet model).
    const bool mirrorInformative = slice.id.elevations.thetaIDeg != slice.id.elevations.thetaVDeg;
    score.informative = mirrorInformative;
    sum = diagonalAsymmetry(signal, mirrorInformative);
  }
  score.score = std::sqrt(sum.squares / sum.terms);
  return score;
}

// The verdict and its sentence from the scores.
void decide(IsotropyVerdict& verdict, const IsotropyParams& params) {
  const bool axialSays = verdict.axialScore > params.axialThreshold;
  const bool diagonalSays = verdict.diagonalScore > params.diagonalThreshold;
  const bool priorSays = verdict.priorScoreRatio < params.priorScoreRatio;
  verdict.isotropic = !axialSays && !diagonalSays && !priorSays;
  std::ostringstream reason;
  if (axialSays) {
    reason << "anisotropic: an axial slice varies (RMS log spread " << verdict.axialScore << " > "
           << params.axialThreshold << ")";
  } else if (priorSays) {
    reason << "anisotropic: half-vector anisotropy terms explain the samples far better than an "
           << "isotropic fit (GCV ratio " << verdict.priorScoreRatio << " < "
           << params.priorScoreRatio << "); measure the axial slices too";
  } else if (diagonalSays) {
    reason << "anisotropic: a diagonal slice is not half-turn/mirror symmetric (RMS log asymmetry "
           << verdict.diagonalScore << " > " << params.diagonalThreshold
           << "); measure the axial slices too";
  } else if (!verdict.informative) {
    reason << "cannot tell: equal-elevation diagonal slices cannot show anisotropy "
           << "(reciprocity and central symmetry make them symmetric); measure a mixed-elevation "
           << "diagonal sweep (30/75 or 75/30) or the axial sweeps";
  } else {
    reason << "no anisotropy seen (GCV ratio " << verdict.priorScoreRatio << ", diagonal asymmetry "
           << verdict.diagonalScore << "); the diagonal sweeps suffice";
  }
  verdict.reason = reason.str();
}

}  // namespace

bool IsotropyParams::isValid(std::string* error) const {
  if (!(floorFraction > 0.0 && floorFraction < 1.0)) {
    if (error) *error = "floor fraction must lie in (0, 1)";
    return false;
  }
  if (!(diagonalThreshold > 0.0) || !(axialThreshold > 0.0)) {
    if (error) *error = "thresholds must be positive";
    return false;
  }
  if (!(priorScoreRatio > 0.0 && priorScoreRatio <= 1.0)) {
    if (error) *error = "prior score ratio must lie in (0, 1]";
    return false;
  }
  return true;
}

IsotropyVerdict testIsotropy(const SliceSet& slices, const IsotropyParams& params) {
  std::string error;
  if (!params.isValid(&error)) throw PriorError("isotropy test: " + error);
  const double floor = logFloor(slices, params);

  IsotropyVerdict verdict;
  bool anyUsable = false;
  for (const Slice& slice : slices.slices()) {
    if (slice.samples.size() < 2) continue;
    anyUsable = true;
    const SliceIsotropyScore score = scoreSlice(slice, floor);
    verdict.slices.push_back(score);
    double& worst = slice.id.kind == SliceKind::Axial ? verdict.axialScore : verdict.diagonalScore;
    worst = std::max(worst, score.score);
  }
  if (!anyUsable) throw PriorError("isotropy test: no slice has two or more samples");
  verdict.informative =
      std::any_of(slices.slices().begin(), slices.slices().end(), [](const Slice& s) {
        return s.id.kind == SliceKind::Axial ||
               s.id.elevations.thetaIDeg != s.id.elevations.thetaVDeg;
      });
  decide(verdict, params);
  return verdict;
}

IsotropyVerdict testIsotropy(const SliceSet& slices, const PriorModel& model,
                             const IsotropyParams& params) {
  IsotropyVerdict verdict = testIsotropy(slices, params);
  if (!verdict.informative) return verdict;
  PriorReport report;
  PriorParams fit;
  fit.anisotropyScoreRatio = params.priorScoreRatio;
  fit.readAtMeasuredAngles = params.readAtMeasuredAngles;
  reconstructWithPrior(slices, model, fit, &report);
  if (report.isotropicScore > 0.0 && std::isfinite(report.anisotropicScore))
    verdict.priorScoreRatio = report.anisotropicScore / report.isotropicScore;
  decide(verdict, params);
  return verdict;
}

}  // namespace slicecap::prior
