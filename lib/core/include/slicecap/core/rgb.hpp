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
  /// \brief Plain average of the three channels (the "monospectral" value of METHOD.md 4.2).
  constexpr double mean() const { return (channel[0] + channel[1] + channel[2]) / 3.0; }
  constexpr double maxChannel() const { return std::max({channel[0], channel[1], channel[2]}); }
  constexpr double minChannel() const { return std::min({channel[0], channel[1], channel[2]}); }

  constexpr Rgb& operator+=(const Rgb& o) {
    for (std::size_t c = 0; c < 3; ++c)
      channel[c] += o.channel[c];
    return *this;
  }
  constexpr Rgb& operator-=(const Rgb& o) {
    for (std::size_t c = 0; c < 3; ++c)
      channel[c] -= o.channel[c];
    return *this;
  }
  constexpr Rgb& operator*=(double s) {
    for (double& v : channel)
      v *= s;
    return *this;
  }
  friend constexpr Rgb operator+(Rgb a, const Rgb& b) { return a += b; }
  friend constexpr Rgb operator-(Rgb a, const Rgb& b) { return a -= b; }
  friend constexpr Rgb operator*(Rgb a, double s) { return a *= s; }
  friend constexpr Rgb operator*(double s, Rgb a) { return a *= s; }
  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;
};

/// \brief (1 - t) a + t b, per channel.
constexpr Rgb lerp(const Rgb& a, const Rgb& b, double t) {
  return a * (1.0 - t) + b * t;
}

}  // namespace slicecap
