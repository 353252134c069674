// The response fit: Debevec-Malik least squares in ln(linear) over ln(code), on mean codes of
// reference areas, with the bracket's plan and the fit's options.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/response_curve.hpp"

namespace slicecap::capture {

bool BracketPlan::isValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = "bracket plan: " + why;
    return false;
  };
  if (static_cast<int>(factors.size()) < ResponseFitParams{}.minExposures)
    return fail(std::to_string(factors.size()) + " exposures, at least " +
                std::to_string(ResponseFitParams{}.minExposures) + " are needed");
  for (std::size_t i = 0; i < factors.size(); ++i) {
    if (!(factors[i] > 0.0) || !std::isfinite(factors[i]))
      return fail("factor " + std::to_string(i) + " is not a positive number");
    if (i > 0 && !(factors[i] > factors[i - 1]))
      return fail("factor " + std::to_string(i) + " does not rise above the one before");
  }
  return true;
}

std::vector<hal::ExposureSetting> BracketPlan::settings(const hal::ExposureSetting& metered,
                                                         double maxExposureUs,
                                                         double maxGain) const {
  std::vector<hal::ExposureSetting> out;
  for (const double factor : factors) {
    const double wantedUs = metered.exposureUs * factor;
    const double exposureUs = std::min(wantedUs, maxExposureUs);
    // The metered gain (nullopt: the camera's default, left alone) unless the exposure is capped.
    std::optional<double> gain = metered.gain;
    if (wantedUs > exposureUs) {
      const double base = metered.gain.value_or(1.0);
      gain = std::min(base * wantedUs / exposureUs, std::max(base, maxGain));
    }
    out.push_back({exposureUs, gain});
  }
  return out;
}

bool ResponseFitParams::isValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = "response fit: " + why;
    return false;
  };
  if (!(darkCode >= 0.0 && clipCode <= 255.0 && clipCode - darkCode >= 16.0))
    return fail("dark code " + std::to_string(darkCode) + " and clip code " +
                std::to_string(clipCode) + " must leave at least 16 codes between them in 0..255");
  if (!(areaMm > 0.5)) return fail("area size " + std::to_string(areaMm) + " mm is under 0.5 mm");
  if (!(insetFraction >= 0.0 && insetFraction < 0.5))
    return fail("inset fraction " + std::to_string(insetFraction) + " is outside [0, 0.5)");
  if (minPixels < 1) return fail("min pixels must be at least 1");
  if (minExposures < 2) return fail("min exposures must be at least 2");
  if (!(smoothness >= 0.0) || !std::isfinite(smoothness)) return fail("smoothness is negative");
  if (minMarkers < 1) return fail("min markers must be at least 1");
  if (!(maxRmsLogResidual > 0.0)) return fail("the largest RMS residual must be positive");
  return true;
}

void checkResponseResidual(const ResponseFit& fit, const ResponseFitParams& params,
                           const std::string& source) {
  if (fit.rmsLogResidual <= params.maxRmsLogResidual) return;
  char figures[128];
  std::snprintf(figures, sizeof figures, "RMS residual %.1f %%, above the %.1f %% allowed",
                100.0 * fit.rmsLogResidual, 100.0 * params.maxRmsLogResidual);
  throw ResponseCurveMisfit(
      source + ": the measured response curve does not fit its bracket (" + figures +
          "): the camera's processing changes its curve from frame to frame (adaptive "
          "contrast: a Raspberry Pi's rpi.contrast ce_enable), so no one curve decodes its "
          "frames. Use RAW (camera_raw = auto or on), slicecap's tuning file (tuning_file = "
          "auto, a camera module 3), or a camera whose processing is fixed",
      fit.rmsLogResidual, params.maxRmsLogResidual);
}

std::string ResponseFit::summary() const {
  char line[256];
  std::snprintf(line, sizeof line,
                "response measured over codes %.1f..%.1f from %d exposures (%d observations, %d "
                "clipped or dark left out), RMS residual %.2f %%",
                lowestCode, highestCode, exposures, observationsUsed, observationsLeftOut,
                100.0 * rmsLogResidual);
  return line;
}

namespace {

// Distinct values, 1 % apart (the camera quantises exposure to its line time).
int distinctExposures(const std::vector<const ResponseObservation*>& used) {
  std::vector<double> values;
  for (const ResponseObservation* o : used) values.push_back(o->exposure);
  std::sort(values.begin(), values.end());
  int count = 0;
  double last = -1.0;
  for (const double v : values)
    if (count == 0 || v > last * 1.01) ++count, last = v;
  return count;
}

// The observations the fit can use: positive weight, exposure and albedo, and a code between the
// dark and clip codes; the clipped or dark ones are counted in fit.observationsLeftOut.
std::vector<const ResponseObservation*> usableObservations(
    const std::vector<ResponseObservation>& observations, const ResponseFitParams& params,
    ResponseFit& fit) {
  std::vector<const ResponseObservation*> used;
  for (const ResponseObservation& o : observations) {
    if (!(o.weight > 0.0) || !(o.exposure > 0.0) || !(o.albedo > 0.0)) continue;
    if (o.code <= params.darkCode || o.code >= params.clipCode) {
      ++fit.observationsLeftOut;
      continue;
    }
    used.push_back(&o);
  }
  return used;
}

// Throws ResponseFitError unless the usable observations span enough exposures and codes; fills
// fit.exposures, fit.lowestCode and fit.highestCode.
void checkBracketCoverage(const std::vector<const ResponseObservation*>& used,
                          const ResponseFitParams& params, const std::string& source,
                          ResponseFit& fit) {
  if (used.empty())
    throw ResponseFitError(source + ": every reference area is clipped (code >= " +
                           std::to_string(int(params.clipCode)) + ") or black (code <= " +
                           std::to_string(int(params.darkCode)) +
                           ") in every frame: meter with the LED on and the target in view, or "
                           "widen the bracket (BracketPlan::factors)");
  fit.exposures = distinctExposures(used);
  if (fit.exposures < params.minExposures)
    throw ResponseFitError(source + ": " + std::to_string(fit.exposures) +
                           " distinct exposures with usable references, at least " +
                           std::to_string(params.minExposures) +
                           " are needed: the camera must accept exposure locks (check "
                           "exposure and gain limits) and the bracket span x1/32..x4");
  double lowest = 255.0, highest = 0.0;
  for (const ResponseObservation* o : used)
    lowest = std::min(lowest, o->code), highest = std::max(highest, o->code);
  fit.lowestCode = lowest;
  fit.highestCode = highest;
}

// The unknown curve: ln(linear) at knots over the codes the observations span, linear in
// ln(code) between (code 0 has no logarithm: the first knot is at 1 or above).
struct KnotGrid {
  std::vector<int> codes;
  int first = 0, last = 0;

  int count() const { return static_cast<int>(codes.size()); }
  double u(int knot) const { return std::log(double(codes[knot])); }
  int segment(double code) const {
    const auto upper = std::upper_bound(codes.begin(), codes.end(), code);
    return std::clamp(static_cast<int>(upper - codes.begin()) - 1, 0, count() - 2);
  }
};

// Throws ResponseFitError when the codes span fewer than 16.
KnotGrid placeKnots(double lowest, double highest, const std::string& source) {
  KnotGrid grid;
  grid.first = std::max(1, static_cast<int>(std::floor(lowest)));
  grid.last = std::max(grid.first + 1, static_cast<int>(std::ceil(highest)));
  if (grid.last - grid.first < 16)
    throw ResponseFitError(source + ": the references cover codes " + std::to_string(lowest) +
                           ".." + std::to_string(highest) +
                           " only; the bracket must spread them over most of 0..255 (widen "
                           "BracketPlan::factors, check that the exposure locks took effect)");
  // Knots about 10 % apart in code (every code near black, where the curve bends most in
  // ln-ln terms), at most 8 codes apart: enough observations between two knots to average their
  // noise (about 1 % each on a Pi-like sensor), close enough for an ISP table's kinks.
  std::vector<int>& knotCodes = grid.codes;
  knotCodes.push_back(grid.first);
  while (knotCodes.back() < grid.last)
    knotCodes.push_back(std::min(
        grid.last, knotCodes.back() +
                       std::clamp(static_cast<int>(std::lround(knotCodes.back() * 0.1)), 1, 8)));
  return grid;
}

// One unknown per reference area after the knots: ln of its linear value.
std::map<int, int> areaColumns(const std::vector<const ResponseObservation*>& used, int knots) {
  std::map<int, int> areaColumn;
  for (const ResponseObservation* o : used)
    areaColumn.emplace(o->area, knots + static_cast<int>(areaColumn.size()));
  return areaColumn;
}

// The weighted least-squares solution: ln(linear) at each knot, then ln of each area's value.
Eigen::VectorXd solveLogResponse(const std::vector<const ResponseObservation*>& used,
                                 const KnotGrid& grid, const std::map<int, int>& areaColumn,
                                 const ResponseFitParams& params) {
  const int knots = grid.count();
  const int unknowns = knots + static_cast<int>(areaColumn.size());
  const int rows = static_cast<int>(used.size()) + std::max(0, knots - 2) + 1;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, unknowns);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(rows);
  int row = 0;
  double largestWeight = 0.0;
  for (const ResponseObservation* o : used) {
    const int k = grid.segment(o->code);
    const double t = (std::log(o->code) - grid.u(k)) / (grid.u(k + 1) - grid.u(k));
    a(row, k) = o->weight * (1.0 - t);
    a(row, k + 1) = o->weight * t;
    a(row, areaColumn.at(o->area)) = -o->weight;
    b(row) = o->weight * std::log(o->exposure * o->albedo);
    largestWeight = std::max(largestWeight, o->weight);
    ++row;
  }
  // Curvature of ln(linear) over ln(code), integrated: zero for a power law, so the penalty
  // bridges codes no observation has with the local gamma.
  for (int k = 1; k + 1 < knots; ++k) {
    const double h0 = grid.u(k) - grid.u(k - 1), h1 = grid.u(k + 1) - grid.u(k), span = h0 + h1;
    const double scale = std::sqrt(params.smoothness * span / 2.0) * 2.0 / span;
    a(row, k - 1) = scale / h0;
    a(row, k) = -scale * (1.0 / h0 + 1.0 / h1);
    a(row, k + 1) = scale / h1;
    ++row;
  }
  // The global scale: ln(linear) = 0 at the highest knot (renormalised below).
  a(row, knots - 1) = 1e3 * std::max(largestWeight, 1.0);
  return a.householderQr().solve(b);
}

// RMS of the unweighted ln residuals of the used observations under the solution x.
double rmsLogResidual(const std::vector<const ResponseObservation*>& used, const KnotGrid& grid,
                      const std::map<int, int>& areaColumn, const Eigen::VectorXd& x) {
  double sumSquares = 0.0;
  for (const ResponseObservation* o : used) {
    const int k = grid.segment(o->code);
    const double t = (std::log(o->code) - grid.u(k)) / (grid.u(k + 1) - grid.u(k));
    const double residual = (1.0 - t) * x(k) + t * x(k + 1) - x(areaColumn.at(o->area)) -
                            std::log(o->exposure * o->albedo);
    sumSquares += residual * residual;
  }
  return std::sqrt(sumSquares / double(used.size()));
}

// Throws ResponseFitError at the first knot interval where the fitted curve does not rise.
void checkMonotone(const KnotGrid& grid, const Eigen::VectorXd& x, const std::string& source) {
  const std::vector<int>& knotCodes = grid.codes;
  for (int k = 1; k < grid.count(); ++k)
    if (!(x(k) > x(k - 1)))
      throw ResponseFitError(
          source + ": the fitted response falls between codes " + std::to_string(knotCodes[k - 1]) +
          " and " + std::to_string(knotCodes[k]) +
          " (not monotone): the frames disagree with their reported exposures. Keep the LED on "
          "and the room light steady through the bracket, and check that the camera reports each "
          "frame's own exposure and gain");
}

// The "measured" tone curve: the fitted knots scaled to linear 1 at code 255.
ToneCurve tabulateCurve(const KnotGrid& grid, const Eigen::VectorXd& x) {
  const int knots = grid.count();
  const std::vector<int>& knotCodes = grid.codes;
  // Linear 1 where the slope of the last knot interval, carried on, reaches code 255.
  std::vector<double> linear(knots);
  for (int k = 0; k < knots; ++k) linear[k] = std::exp(x(k));
  const double slope =
      (linear[knots - 1] - linear[knots - 2]) / (knotCodes[knots - 1] - knotCodes[knots - 2]);
  const double atFullScale = linear[knots - 1] + slope * (255.0 - grid.last);
  // Between knots the curve is linear in ln-ln terms: tabulated at every code.
  std::vector<std::pair<double, double>> points{{0.0, 0.0}};
  for (int code = std::max(grid.first, 1); code <= std::min(grid.last, 254); ++code) {
    const int k = grid.segment(code);
    const double t = (std::log(double(code)) - grid.u(k)) / (grid.u(k + 1) - grid.u(k));
    points.emplace_back(std::exp((1.0 - t) * x(k) + t * x(k + 1)) / atFullScale, code / 255.0);
  }
  points.emplace_back(1.0, 1.0);
  return ToneCurve("measured", std::move(points));
}

}  // namespace

ResponseFit fitResponseCurve(const std::vector<ResponseObservation>& observations,
                             const ResponseFitParams& params, const std::string& source) {
  std::string why;
  if (!params.isValid(&why)) throw CaptureError(why);
  ResponseFit fit;
  const std::vector<const ResponseObservation*> used =
      usableObservations(observations, params, fit);
  checkBracketCoverage(used, params, source, fit);
  const KnotGrid grid = placeKnots(fit.lowestCode, fit.highestCode, source);
  const std::map<int, int> areaColumn = areaColumns(used, grid.count());
  const Eigen::VectorXd x = solveLogResponse(used, grid, areaColumn, params);
  fit.observationsUsed = static_cast<int>(used.size());
  fit.rmsLogResidual = rmsLogResidual(used, grid, areaColumn, x);
  checkMonotone(grid, x, source);
  fit.curve = tabulateCurve(grid, x);
  return fit;
}

}  // namespace slicecap::capture
