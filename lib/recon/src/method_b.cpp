// Method B: two interpolation steps (views, then lights), each weighted by a fitted elevation lobe.
#include "slicecap/recon/method_b.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/elevation_correction.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/measured_subspaces.hpp"

namespace slicecap::recon {
namespace {

constexpr std::array<int, 6> kAllElevationsDeg{0, 15, 30, 45, 60, 75};
constexpr int kLowDeg = kMeasuredElevationsDeg[0];
constexpr int kHighDeg = kMeasuredElevationsDeg[1];

bool isMeasured(int thetaDeg) {
  return thetaDeg == kLowDeg || thetaDeg == kHighDeg;
}

// Known data of one elevation pair: its block, its monospectral mean, and the monospectral values
// of the samples it was measured from (empty for pairs predicted in step 1).
struct PairData {
  Subspace block;
  double mean = 0.0;
  std::vector<double> sampleValues;
};

// The fitted lobe of one line through a low and a high pair, by Ceres, with the closed form as the
// checked fallback. Measured pairs contribute every sample, predicted ones their model mean.
ElevationLobe fitLine(const std::string& line, const PairData& low, const PairData& high,
                      const LobeFitParams& params, MethodBReport* report) {
  std::vector<ElevationSample> samples;
  for (auto [pair, thetaDeg] : {std::pair{&low, kLowDeg}, std::pair{&high, kHighDeg}}) {
    if (pair->sampleValues.empty()) samples.push_back({double(thetaDeg), pair->mean});
    for (double v : pair->sampleValues)
      samples.push_back({double(thetaDeg), v});
  }
  LineFit record{line, fitElevationLobe(samples, params), false};
  ElevationLobe lobe = record.fit.lobe;
  if (!record.fit.converged) {
    lobe = closedFormLobe(kLowDeg, low.mean, kHighDeg, high.mean, params.minimumValue);
    record.usedClosedForm = true;
  }
  if (report) report->fits.push_back(std::move(record));
  return lobe;
}

// The block at `targetDeg` along a line, from the known low and high blocks (docs/method.md §4.2).
// `resample` moves a known block to the target elevation along the varying direction.
template <typename Resample, typename ResampledBlend>
Subspace interpolateAlongLine(const ElevationLobe& lobe, const Subspace& low, const Subspace& high,
                              int targetDeg, Resample resample, ResampledBlend resampledBlend) {
  const double fLow = lobe.shape(kLowDeg);
  const double fHigh = lobe.shape(kHighDeg);
  const double fTarget = lobe.shape(targetDeg);
  if (targetDeg < kLowDeg) return resample(low, targetDeg).scale(fTarget / fLow);
  double t = std::abs(fHigh - fLow) < 1e-12 ? double(targetDeg - kLowDeg) / (kHighDeg - kLowDeg)
                                            : (fTarget - fLow) / (fHigh - fLow);
  t = std::clamp(t, 0.0, 1.0);
  return resampledBlend(low, high, t, targetDeg);
}

Subspace resampleViews(const Subspace& s, int thetaDeg) {
  return s.resampledToViewElevation(thetaDeg);
}
Subspace resampleLights(const Subspace& s, int thetaDeg) {
  return s.resampledToLightElevation(thetaDeg);
}

}  // namespace

bool MethodBReport::allConverged() const {
  return std::all_of(fits.begin(), fits.end(), [](const LineFit& f) { return f.fit.converged; });
}

namespace {

// Method B on slices whose samples sit at their nominal elevations.
Abrdf reconstructAtNominalElevations(const SliceSet& slices, const MethodBParams& params,
                                     MethodBReport* report) {
  std::vector<Subspace> measured =
      reconstructMeasuredSubspaces(slices, params.isotropic, params.torusRule, "Method B");

  // Known blocks keyed by (theta_i, theta_v); step 1 adds the predicted ones.
  std::map<ElevationPair, PairData> known;
  for (std::size_t p = 0; p < kMeasuredPairs.size(); ++p) {
    const ElevationPair pair = kMeasuredPairs[p];
    const Slice* diagonal = slices.find({SliceKind::Diagonal, pair});
    const Slice* axial = params.isotropic ? nullptr : slices.find({SliceKind::Axial, pair});
    PairData data{std::move(measured[p]), 0.0, {}};
    // Every sample counts at its pair's nominal elevations, where it was moved above.
    for (const Slice* slice : {diagonal, axial}) {
      if (!slice) continue;
      for (const SliceSample& s : slice->samples)
        data.sampleValues.push_back(s.value.mean());
    }
    double sum = 0.0;
    for (double v : data.sampleValues)
      sum += v;
    data.mean = sum / double(data.sampleValues.size());
    known.emplace(pair, std::move(data));
  }

  // Step 1: views, at each measured light elevation.
  for (int thetaIDeg : kMeasuredElevationsDeg) {
    const PairData& low = known.at({thetaIDeg, kLowDeg});
    const PairData& high = known.at({thetaIDeg, kHighDeg});
    const ElevationLobe lobe =
        fitLine("views at theta_i " + std::to_string(thetaIDeg), low, high, params.fit, report);
    for (int thetaVDeg : kAllElevationsDeg) {
      if (isMeasured(thetaVDeg)) continue;
      PairData predicted{interpolateAlongLine(lobe, low.block, high.block, thetaVDeg, resampleViews,
                                              Subspace::blendAtViewElevation),
                         low.mean * lobe.shape(thetaVDeg) / lobe.shape(kLowDeg),
                         {}};
      known.emplace(ElevationPair{thetaIDeg, thetaVDeg}, std::move(predicted));
    }
  }
  // Step 2: lights, at every view elevation.
  Abrdf table;
  for (int thetaVDeg : kAllElevationsDeg) {
    const PairData& low = known.at({kLowDeg, thetaVDeg});
    const PairData& high = known.at({kHighDeg, thetaVDeg});
    const ElevationLobe lobe =
        fitLine("lights at theta_v " + std::to_string(thetaVDeg), low, high, params.fit, report);
    low.block.writeTo(table);
    high.block.writeTo(table);
    for (int thetaIDeg : kAllElevationsDeg) {
      if (isMeasured(thetaIDeg)) continue;
      interpolateAlongLine(lobe, low.block, high.block, thetaIDeg, resampleLights,
                           Subspace::blendAtLightElevation)
          .writeTo(table);
    }
  }
  for (float& v : table.values())
    v = std::max(v, 0.0f);
  return table;
}

bool atNominalElevations(const SliceSet& slices) {
  for (const Slice& slice : slices.slices()) {
    for (const SliceSample& s : slice.samples) {
      if (slice.id.kind != SliceKind::Point && (s.light.thetaDeg != slice.id.elevations.thetaIDeg ||
                                                s.view.thetaDeg != slice.id.elevations.thetaVDeg))
        return false;
    }
  }
  return true;
}

}  // namespace

Abrdf reconstructMethodB(const SliceSet& slices, const MethodBParams& params,
                         MethodBReport* report) {
  std::string error;
  if (!params.fit.isValid(&error)) throw ReconArgumentError("Method B: " + error);
  if (atNominalElevations(slices)) return reconstructAtNominalElevations(slices, params, report);
  // The slice-sum reads a slice as a signal of its azimuth alone, so samples taken a degree or two
  // off their pair's elevations are first moved to them: along a fitted elevation lobe for a
  // first reconstruction, then along that reconstruction's own local change with elevation at
  // each sample's azimuths, which follows highlights and sheens one lobe cannot
  // (elevation_correction.hpp).
  const Abrdf first =
      reconstructAtNominalElevations(correctedToNominalElevations(slices), params, nullptr);
  return reconstructAtNominalElevations(correctedToNominalElevations(slices, first), params,
                                        report);
}

}  // namespace slicecap::recon
