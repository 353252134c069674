// A 360-degree periodic RGB signal known at arbitrary positions, read by periodic linear
// interpolation.
#pragma once

#include <span>
#include <vector>

#include "slicecap/core/rgb.hpp"

namespace slicecap::recon {

/// \brief One known value of a periodic signal.
struct SignalPoint {
  double positionDeg = 0.0;
  Rgb value;
};

/// \brief A slice as a 2-pi periodic 1-D signal (docs/method.md §2.4). Positions are wrapped to [0, 360);
/// points that share a position are averaged. Between neighbours (cyclically) the value is linear.
class PeriodicSignal {
 public:
  /// \brief Throws ReconArgumentError when `points` is empty or holds a non-finite number.
  explicit PeriodicSignal(std::span<const SignalPoint> points);

  /// \brief The interpolated value at any position (wrapped first).
  Rgb at(double positionDeg) const;
  /// \brief The same value as at(positionDeg), searched from `cursor` (any value; the call leaves
  /// the found interval there): a few steps instead of a binary search when the positions come in
  /// order, as along a ring of a subspace.
  Rgb at(double positionDeg, std::size_t& cursor) const;

  /// \brief Per-channel minimum and maximum over the known points.
  const Rgb& minimum() const { return minimum_; }
  const Rgb& maximum() const { return maximum_; }
  /// \brief The distinct known points, sorted by position.
  const std::vector<SignalPoint>& points() const { return points_; }

 private:
  Rgb interpolate(double wrappedDeg, std::size_t after) const;

  std::vector<SignalPoint> points_;
  Rgb minimum_, maximum_;
};

}  // namespace slicecap::recon
