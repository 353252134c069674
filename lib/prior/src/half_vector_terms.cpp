// Half-vector anisotropy terms of a light/view pair and of the whole grid.
#include "half_vector_terms.hpp"

#include <algorithm>
#include <cmath>

#include "slicecap/core/angles.hpp"

namespace slicecap::prior {

HalfVectorTerms halfVectorTerms(const UnitVector& light, const UnitVector& view) {
  const double x = light.x + view.x, y = light.y + view.y, z = light.z + view.z;
  const double thetaHDeg = radToDeg(std::atan2(std::sqrt(x * x + y * y), z));
  const double phiH = std::atan2(y, x);
  HalfVectorTerms terms{};
  int t = 0;
  for (int node = 1; node <= 6; ++node)
    terms[t++] = std::max(0.0, 1.0 - std::abs(thetaHDeg - 15.0 * node) / 15.0);
  for (int m = 1; m <= 2; ++m) {
    const double c = std::cos(2 * m * phiH), s = std::sin(2 * m * phiH);
    for (int node = 1; node <= 6; ++node) {
      const double hat = std::max(0.0, 1.0 - std::abs(thetaHDeg - 15.0 * node) / 15.0);
      terms[t++] = hat * c;
      terms[t++] = hat * s;
    }
  }
  return terms;
}

const std::array<HalfVectorTerms, 81 * 81>& gridHalfVectorTerms() {
  static const auto terms = [] {
    std::array<HalfVectorTerms, 81 * 81> all{};
    for (int l = 0; l < 81; ++l) {
      for (int v = 0; v < 81; ++v)
        all[l * 81 + v] =
            halfVectorTerms(toUnitVector(bonn::direction(l)), toUnitVector(bonn::direction(v)));
    }
    return all;
  }();
  return terms;
}

}  // namespace slicecap::prior
