// The 81 x 81 x RGB table of an apparent BRDF on the Bonn grid, [light][view][rgb], linear floats.
#pragma once

#include <cassert>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap {

/// \brief A full ABRDF table: 81 light x 81 view directions x 3 channels of linear float32 BRDF
/// values (1/sr), light-major in the Bonn order (docs/method.md §1.3). Zero-initialised.
class Abrdf {
 public:
  static constexpr int kDirections = bonn::kDirectionCount;
  static constexpr std::size_t kValueCount = std::size_t{kDirections} * kDirections * 3;

  Abrdf() : values_(kValueCount, 0.0f) {}

  /// \brief Value at (light index, view index); indices are not range-checked (assert only).
  Rgb at(int light, int view) const {
    const std::size_t o = offset(light, view);
    return {values_[o], values_[o + 1], values_[o + 2]};
  }
  void set(int light, int view, const Rgb& value) {
    const std::size_t o = offset(light, view);
    for (std::size_t c = 0; c < 3; ++c)
      values_[o + c] = static_cast<float>(value[c]);
  }

  float& channel(int light, int view, int c) { return values_[offset(light, view) + c]; }
  float channel(int light, int view, int c) const { return values_[offset(light, view) + c]; }

  /// \brief All 19683 values in storage order [light][view][rgb].
  std::span<float> values() { return values_; }
  std::span<const float> values() const { return values_; }

  friend bool operator==(const Abrdf&, const Abrdf&) = default;

 private:
  static std::size_t offset(int light, int view) {
    assert(light >= 0 && light < kDirections && view >= 0 && view < kDirections);
    return (std::size_t(light) * kDirections + std::size_t(view)) * 3;
  }
  std::vector<float> values_;
};

/// \brief The table of a BRDF given as f_r(toLight, toView) (unit vectors, z up, 1/sr) at the 81
/// Bonn directions: what every analytic material (built-in models, fits, a format's BRDF) is
/// compared through. Throws what `brdf` throws.
Abrdf tabulateOnGrid(const std::function<Rgb(const UnitVector& toLight, const UnitVector& toView)>& brdf);

}  // namespace slicecap
