// A linear RGB triple of doubles, with the little arithmetic the reconstruction needs.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

namespace slicecap {

/// \brief Linear RGB value (BRDF in 1/sr in most uses). Channels are indexed 0 = R, 1 = G, 2 = B.
struct Rgb {
  std::array<double, 3> channel{0.0, 0.0, 0.0};

  constexpr Rgb() = default;
  constexpr Rgb(double r, double g, double b) : channel{r, g, b} {}
  /// \brief The same value in all three channels.
  static constexpr Rgb gray(double v) { return {v, v, v}; }

  constexpr double& operator[](std::size_t c) { return channel[c]; }
  constexpr double operator[](std::size_t c) const { return channel[c]; }
  constexpr double r() const { return channel[0]; }
  constexpr double g() const { return channel[1]; }
  constexpr double b() const { return channel[2]; }
  /// \brief Plain average of the three channels (the "monospectral" value of docs/method.md §4.2).
  constexpr double mean() const { return (channel[0] + channel[1] + channel[2]) / 3.0; }
  constexpr double maxChannel() const { return std::max({channel[0], channel[1], channel[2]}); }
  constexpr double minChannel() const { return std::min({channel[0], channel[1], channel[2]}); }

  // Per channel, written out: GCC -O2 keeps a loop's or a copy's temporaries on the stack, and the
  // reconstruction does a few of these per table entry (lerp below).
  constexpr Rgb& operator+=(const Rgb& o) {
    channel = {channel[0] + o.channel[0], channel[1] + o.channel[1], channel[2] + o.channel[2]};
    return *this;
  }
  constexpr Rgb& operator-=(const Rgb& o) {
    channel = {channel[0] - o.channel[0], channel[1] - o.channel[1], channel[2] - o.channel[2]};
    return *this;
  }
  constexpr Rgb& operator*=(double s) {
    channel = {channel[0] * s, channel[1] * s, channel[2] * s};
    return *this;
  }
  friend constexpr Rgb operator+(const Rgb& a, const Rgb& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
  }
  friend constexpr Rgb operator-(const Rgb& a, const Rgb& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  }
  friend constexpr Rgb operator*(const Rgb& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
  friend constexpr Rgb operator*(double s, const Rgb& a) { return {a[0] * s, a[1] * s, a[2] * s}; }
  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;
};

/// \brief (1 - t) a + t b, per channel.
constexpr Rgb lerp(const Rgb& a, const Rgb& b, double t) {
  // Written out per channel (see above): resampling spends most of its time here.
  const double s = 1.0 - t;
  return {a[0] * s + b[0] * t, a[1] * s + b[1] * t, a[2] * s + b[2] * t};
}

}  // namespace slicecap
