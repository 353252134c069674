// The separable elevation lobe and the move of each sample to its nominal elevation pair.
#include "slicecap/recon/elevation_correction.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <set>

#include "slicecap/core/angles.hpp"

namespace slicecap::recon {
namespace {

double logCos(double thetaDeg) {
  return std::log(std::cos(degToRad(thetaDeg)));
}

bool onSlice(const Slice& slice) {
  return slice.id.kind != SliceKind::Point;
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
    for (SliceSample s : slice.samples) {
      if (onSlice(slice)) {
        const double lightDeg = slice.id.elevations.thetaIDeg;
        const double viewDeg = slice.id.elevations.thetaVDeg;
        if (s.light.thetaDeg != lightDeg || s.view.thetaDeg != viewDeg) {
          // Past the horizon a cosine ratio means nothing; such a sample keeps its value.
          if (s.light.thetaDeg < 90.0 && s.view.thetaDeg < 90.0) {
            const double logFactor =
                lobe.lightExponent * (logCos(lightDeg) - logCos(s.light.thetaDeg)) +
                lobe.viewExponent * (logCos(viewDeg) - logCos(s.view.thetaDeg));
            s.value = s.value * std::exp(logFactor);
          }
          s.light.thetaDeg = lightDeg;
          s.view.thetaDeg = viewDeg;
        }
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
