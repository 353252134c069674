// Periodic linear interpolation over irregular, possibly sparse slice samples.
#include "slicecap/recon/periodic_signal.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slicecap/core/angles.hpp"
#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {

PeriodicSignal::PeriodicSignal(std::span<const SignalPoint> points) {
  if (points.empty()) throw ReconArgumentError("periodic signal: no samples");
  std::vector<SignalPoint> sorted;
  sorted.reserve(points.size());
  for (const SignalPoint& p : points) {
    bool finite = std::isfinite(p.positionDeg);
    for (std::size_t c = 0; c < 3; ++c)
      finite = finite && std::isfinite(p.value[c]);
    if (!finite) throw ReconArgumentError("periodic signal: non-finite sample");
    sorted.push_back({wrapDeg360(p.positionDeg), p.value});
  }
  std::sort(sorted.begin(), sorted.end(), [](const SignalPoint& a, const SignalPoint& b) {
    return a.positionDeg < b.positionDeg;
  });

  // Average samples at the same position: a real capture may bin two frames at one azimuth.
  constexpr double kSamePositionDeg = 1e-9;
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    Rgb sum;
    while (j < sorted.size() && sorted[j].positionDeg - sorted[i].positionDeg < kSamePositionDeg) {
      sum += sorted[j].value;
      ++j;
    }
    points_.push_back({sorted[i].positionDeg, sum * (1.0 / double(j - i))});
    i = j;
  }
  minimum_ = maximum_ = points_.front().value;
  for (const SignalPoint& p : points_) {
    for (std::size_t c = 0; c < 3; ++c) {
      minimum_[c] = std::min(minimum_[c], p.value[c]);
      maximum_[c] = std::max(maximum_[c], p.value[c]);
    }
  }
}

Rgb PeriodicSignal::at(double positionDeg) const {
  if (points_.size() == 1) return points_.front().value;
  const double x = wrapDeg360(positionDeg);
  const auto after =
      std::upper_bound(points_.begin(), points_.end(), x,
                       [](double v, const SignalPoint& p) { return v < p.positionDeg; });
  return interpolate(x, static_cast<std::size_t>(after - points_.begin()));
}

Rgb PeriodicSignal::at(double positionDeg, std::size_t& cursor) const {
  if (points_.size() == 1) return points_.front().value;
  const double x = wrapDeg360(positionDeg);
  // The same index as the binary search above: the first point strictly after x.
  std::size_t after = std::min(cursor, points_.size());
  while (after > 0 && points_[after - 1].positionDeg > x)
    --after;
  while (after < points_.size() && points_[after].positionDeg <= x)
    ++after;
  cursor = after;
  return interpolate(x, after);
}

// The value at a wrapped position in the interval before points_[after], cyclically.
Rgb PeriodicSignal::interpolate(double wrappedDeg, std::size_t after) const {
  const SignalPoint& hi = after == points_.size() ? points_.front() : points_[after];
  const SignalPoint& lo = after == 0 ? points_.back() : points_[after - 1];
  double span = hi.positionDeg - lo.positionDeg;
  double offset = wrappedDeg - lo.positionDeg;
  if (span <= 0.0) span += 360.0;
  if (offset < 0.0) offset += 360.0;
  return lerp(lo.value, hi.value, offset / span);
}

}  // namespace slicecap::recon
