// The separable elevation lobe and the move of each sample to its nominal elevation pair.
#include "slicecap/recon/elevation_correction.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

#include "slicecap/core/angles.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::recon {
namespace {

double logCos(double thetaDeg) {
  return std::log(std::cos(degToRad(thetaDeg)));
}

bool onSlice(const Slice& slice) {
  return slice.id.kind != SliceKind::Point;
}

// The sample at its pair's nominal elevations, its value moved along `lobe`; unchanged to the bit
// when it is there already. Past the horizon a cosine ratio means nothing: such a sample keeps
// its value.
SliceSample movedToNominal(SliceSample s, ElevationPair pair, const SeparableElevationLobe& lobe) {
  const double lightDeg = pair.thetaIDeg, viewDeg = pair.thetaVDeg;
  if (s.light.thetaDeg == lightDeg && s.view.thetaDeg == viewDeg) return s;
  if (s.light.thetaDeg < 90.0 && s.view.thetaDeg < 90.0) {
    const double logFactor = lobe.lightExponent * (logCos(lightDeg) - logCos(s.light.thetaDeg)) +
                             lobe.viewExponent * (logCos(viewDeg) - logCos(s.view.thetaDeg));
    if (std::isfinite(logFactor)) s.value = s.value * std::exp(logFactor);
  }
  s.light.thetaDeg = lightDeg;
  s.view.thetaDeg = viewDeg;
  return s;
}

}  // namespace

SeparableElevationLobe fitSeparableElevationLobe(const SliceSet& slices) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  std::set<int> lightElevations, viewElevations;
  for (const Slice& slice : slices.slices()) {
    if (!onSlice(slice)) continue;
    for (const SliceSample& s : slice.samples) {
      const double mean = s.value.mean();
      if (!(mean > 0.0) || !std::isfinite(mean) || !(s.light.thetaDeg < 90.0) ||
          !(s.view.thetaDeg < 90.0))
        continue;
      const Eigen::Vector3d row(1.0, logCos(s.light.thetaDeg), logCos(s.view.thetaDeg));
      normal += row * row.transpose();
      right += row * std::log(mean);
      lightElevations.insert(slice.id.elevations.thetaIDeg);
      viewElevations.insert(slice.id.elevations.thetaVDeg);
    }
  }
  if (lightElevations.size() < 2 || viewElevations.size() < 2) return {};
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
  if (lu.rank() < 3) return {};
  const Eigen::Vector3d x = lu.solve(right);
  if (!x.allFinite()) return {};
  return {x[1], x[2]};
}

SliceSet correctedToNominalElevations(const SliceSet& slices, const SeparableElevationLobe& lobe) {
  SliceSet out;
  for (const Slice& slice : slices.slices()) {
    for (const SliceSample& s : slice.samples)
      out.add(slice.id, onSlice(slice) ? movedToNominal(s, slice.id.elevations, lobe) : s);
  }
  return out;
}

namespace {

// The slope per degree of log(channel mean) of `table` along the light (or view) elevation at the
// nominal pair, between the rings around it, at the given azimuths; 0 where a value is (nearly) 0.
double localLogSlopePerDeg(const Abrdf& table, ElevationPair pair, const AzimuthPair& azimuths,
                           bool alongLight, double floor) {
  const int nominal = alongLight ? pair.thetaIDeg : pair.thetaVDeg;
  const int below = std::max(0, nominal - 15);
  const int above = std::min(75, nominal + 15);
  if (above == below) return 0.0;
  auto valueAt = [&](int thetaDeg) {
    ElevationPair at = pair;
    (alongLight ? at.thetaIDeg : at.thetaVDeg) = thetaDeg;
    return sampleTable(table, at, azimuths).mean();
  };
  const double high = valueAt(above), low = valueAt(below);
  if (!(high > floor) || !(low > floor)) return 0.0;
  return (std::log(high) - std::log(low)) / double(above - below);
}

}  // namespace

SliceSet correctedToNominalElevations(const SliceSet& slices, const Abrdf& localModel) {
  double largest = 0.0;
  for (float v : localModel.values())
    largest = std::max(largest, double(v));
  // Values clipped to 0 (or nearly) have no slope worth following.
  const double floor = std::max(1e-9 * largest, 1e-30);
  SliceSet out;
  for (const Slice& slice : slices.slices()) {
    for (SliceSample s : slice.samples) {
      const ElevationPair pair = slice.id.elevations;
      if (onSlice(slice) &&
          (s.light.thetaDeg != pair.thetaIDeg || s.view.thetaDeg != pair.thetaVDeg)) {
        const AzimuthPair azimuths{wrapDeg360(s.light.phiDeg), wrapDeg360(s.view.phiDeg)};
        const double logFactor = localLogSlopePerDeg(localModel, pair, azimuths, true, floor) *
                                     (pair.thetaIDeg - s.light.thetaDeg) +
                                 localLogSlopePerDeg(localModel, pair, azimuths, false, floor) *
                                     (pair.thetaVDeg - s.view.thetaDeg);
        if (std::isfinite(logFactor)) s.value = s.value * std::exp(logFactor);
        s.light.thetaDeg = pair.thetaIDeg;
        s.view.thetaDeg = pair.thetaVDeg;
      }
      out.add(slice.id, s);
    }
  }
  return out;
}

SliceSet correctedToNominalElevations(const SliceSet& slices) {
  return correctedToNominalElevations(slices, fitSeparableElevationLobe(slices));
}

}  // namespace slicecap::recon
