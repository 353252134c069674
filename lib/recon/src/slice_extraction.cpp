// Simulated acquisition: slice samples read off a full table at their exact azimuths.
#include "slicecap/recon/slice_extraction.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "slicecap/core/grid_interpolation.hpp"
#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

// The ring taps of an azimuth under the lookup rule; nearest breaks exact half-step ties toward the
// lower index.
std::array<DirectionTap, 2> ringTaps(const Ring& ring, double phiDeg, AzimuthLookup lookup) {
  const std::array<DirectionTap, 2> taps = ringAzimuthTaps(ring, phiDeg);
  if (lookup == AzimuthLookup::Linear) return taps;
  return {{{taps[1].weight > 0.5 ? taps[1].index : taps[0].index, 1.0}, {taps[0].index, 0.0}}};
}

}  // namespace

std::vector<GridWeight> lookupWeights(ElevationPair elevations, const AzimuthPair& azimuths,
                                      AzimuthLookup lookup) {
  std::vector<GridWeight> weights;
  for (const DirectionTap& l :
       ringTaps(bonn::ringAt(elevations.thetaIDeg), azimuths.phiIDeg, lookup)) {
    if (l.weight == 0.0) continue;
    for (const DirectionTap& v :
         ringTaps(bonn::ringAt(elevations.thetaVDeg), azimuths.phiVDeg, lookup)) {
      if (v.weight != 0.0) weights.push_back({l.index, v.index, l.weight * v.weight});
    }
  }
  return weights;
}

Rgb sampleTable(const Abrdf& table, ElevationPair elevations, const AzimuthPair& azimuths,
                AzimuthLookup lookup) {
  Rgb value;
  for (const GridWeight& w : lookupWeights(elevations, azimuths, lookup))
    value += table.at(w.light, w.view) * w.weight;
  return value;
}

bool ExtractionParams::isValid(std::string* error) const {
  if (!stepDeg) return true;
  const double count = 360.0 / *stepDeg;
  if (!std::isfinite(count) || count < 2.0 || count > 360.0 ||
      std::abs(count - std::round(count)) > 1e-9) {
    if (error) *error = "slice step must divide 360 deg into 2 to 360 equal parts";
    return false;
  }
  return true;
}

int samplesPerSlice(ElevationPair pair, const ExtractionParams& params) {
  if (params.stepDeg) return static_cast<int>(std::lround(360.0 / *params.stepDeg));
  return std::max(bonn::ringAt(pair.thetaIDeg).count, bonn::ringAt(pair.thetaVDeg).count);
}

SliceSet extractSlices(const Abrdf& table, const ExtractionParams& params) {
  std::string error;
  if (!params.isValid(&error)) throw ReconArgumentError(error);
  SliceSet slices;
  for (ElevationPair pair : kMeasuredPairs) {
    const int count = samplesPerSlice(pair, params);
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      if (params.diagonalOnly && kind == SliceKind::Axial) continue;
      for (int k = 0; k < count; ++k) {
        const AzimuthPair at = slicePoint(kind, k * 360.0 / count);
        slices.add({kind, pair}, {{double(pair.thetaIDeg), at.phiIDeg},
                                  {double(pair.thetaVDeg), at.phiVDeg},
                                  sampleTable(table, pair, at, params.lookup)});
      }
    }
  }
  return slices;
}

}  // namespace slicecap::recon
