// Slice-sum subspace reconstruction (docs/method.md §3.2-3.4).
#include "slicecap/recon/slice_sum.hpp"

#include <cmath>

#include "slicecap/core/angles.hpp"
#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/errors.hpp"

namespace slicecap::recon {
namespace {

// `cursor` carries the search from one grid point to the next: along a ring the positions come
// in order.
Rgb lookup(const PeriodicSignal& signal, double positionDeg, TorusRule rule, std::size_t& cursor) {
  if (rule == TorusRule::FundamentalSquare) return signal.at(positionDeg, cursor);
  return lerp(signal.at(positionDeg), signal.at(positionDeg + 180.0), 0.5);
}

}  // namespace

SliceCoordinates sliceCoordinates(double phiIDeg, double phiVDeg) {
  // No wrapping before halving: the halving picks the pre-image in the fundamental square.
  return {wrapDeg360((phiIDeg + phiVDeg - kAxialOffsetDeg) / 2.0),
          wrapDeg360(180.0 + (phiVDeg - phiIDeg) / 2.0)};
}

PeriodicSignal toSignal(const Slice& slice) {
  if (slice.samples.empty())
    throw ReconstructionError("slice " + toString(slice.id) + " has no samples");
  if (slice.id.kind == SliceKind::Point)
    throw ReconstructionError("point samples (" + toString(slice.id) + ") lie on no slice");
  std::vector<SignalPoint> points;
  points.reserve(slice.samples.size());
  for (const SliceSample& s : slice.samples)
    points.push_back({sliceParameterDeg(slice.id.kind, s), s.value});
  try {
    return PeriodicSignal(points);
  } catch (const ReconArgumentError& e) {
    throw ReconstructionError("slice " + toString(slice.id) + ": " + e.what());
  }
}

Subspace reconstructSubspace(const Slice& axial, const Slice& diagonal, TorusRule rule) {
  if (axial.id.kind != SliceKind::Axial || diagonal.id.kind != SliceKind::Diagonal ||
      axial.id.elevations != diagonal.id.elevations) {
    throw ReconstructionError("slice-sum needs the axial and diagonal slice of one pair, got " +
                              toString(axial.id) + " and " + toString(diagonal.id));
  }
  const PeriodicSignal a = toSignal(axial);
  const PeriodicSignal d = toSignal(diagonal);
  Subspace out(axial.id.elevations);
  const Ring& lightRing = out.lightRing();
  const Ring& viewRing = out.viewRing();

  Rgb sumLow, sumHigh, low, high;
  for (std::size_t c = 0; c < 3; ++c) {
    sumLow[c] = a.minimum()[c] + d.minimum()[c];
    sumHigh[c] = a.maximum()[c] + d.maximum()[c];
    low[c] = std::min(a.minimum()[c], d.minimum()[c]);
    high[c] = std::max(a.maximum()[c], d.maximum()[c]);
  }
  std::size_t axialCursor = 0, diagonalCursor = 0;
  for (int p = 0; p < lightRing.count; ++p) {
    for (int q = 0; q < viewRing.count; ++q) {
      const SliceCoordinates x = sliceCoordinates(lightRing.azimuthDeg(p), viewRing.azimuthDeg(q));
      const Rgb sum =
          lookup(a, x.axialDeg, rule, axialCursor) + lookup(d, x.diagonalDeg, rule, diagonalCursor);
      Rgb& value = out.at(p, q);
      for (std::size_t c = 0; c < 3; ++c) {
        const double range = sumHigh[c] - sumLow[c];
        const double normalised = range > 0.0 ? (sum[c] - sumLow[c]) / range : 0.0;
        value[c] = normalised * (high[c] - low[c]) + low[c];
      }
    }
  }
  return out;
}

Subspace reconstructIsotropicSubspace(const Slice& diagonal, TorusRule rule) {
  if (diagonal.id.kind != SliceKind::Diagonal) {
    throw ReconstructionError("the isotropic reconstruction needs a diagonal slice, got " +
                              toString(diagonal.id));
  }
  const PeriodicSignal d = toSignal(diagonal);
  Subspace out(diagonal.id.elevations);
  std::size_t cursor = 0;
  for (int p = 0; p < out.lightRing().count; ++p) {
    for (int q = 0; q < out.viewRing().count; ++q) {
      const SliceCoordinates x =
          sliceCoordinates(out.lightRing().azimuthDeg(p), out.viewRing().azimuthDeg(q));
      out.at(p, q) = lookup(d, x.diagonalDeg, rule, cursor);
    }
  }
  return out;
}

}  // namespace slicecap::recon
