// Farthest-point direction selection and the uniform baseline's point samples.
#include "slicecap/recon/uniform_sampling.hpp"

#include <array>
#include <limits>
#include <stdexcept>
#include <string>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

double squaredDistance(const UnitVector& a, const UnitVector& b) {
  return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z);
}

// docs/method.md §6.3's published selection order, (theta, phi) in degrees. Every pick is a farthest
// point, but several were ties (every 75 deg direction is equally far from the pole) that fell by
// floating-point rounding; keeping this order keeps the documented baseline on every platform.
constexpr std::array<std::array<int, 2>, 14> kPublishedOrder{{{0, 0},
                                                              {75, 105},
                                                              {75, 225},
                                                              {75, 0},
                                                              {60, 288},
                                                              {75, 165},
                                                              {60, 54},
                                                              {45, 140},
                                                              {45, 200},
                                                              {45, 340},
                                                              {30, 30},
                                                              {30, 270},
                                                              {60, 252},
                                                              {75, 315}}};

void requireCount(int count) {
  if (count < 1 || count > bonn::kDirectionCount) {
    throw ReconArgumentError("uniform sampling needs 1 to 81 directions, got " +
                             std::to_string(count));
  }
}

}  // namespace

std::vector<int> farthestPointDirections(int count) {
  requireCount(count);
  std::vector<UnitVector> vectors;
  for (int i = 0; i < bonn::kDirectionCount; ++i)
    vectors.push_back(toUnitVector(bonn::direction(i)));
  // nearest[i]: squared distance from direction i to the closest chosen one.
  std::vector<double> nearest(vectors.size(), std::numeric_limits<double>::infinity());
  std::vector<int> chosen;
  auto choose = [&](int index) {
    chosen.push_back(index);
    for (int i = 0; i < bonn::kDirectionCount; ++i)
      nearest[i] = std::min(nearest[i], squaredDistance(vectors[i], vectors[index]));
  };
  for (const auto& [thetaDeg, phiDeg] : kPublishedOrder) {
    if (static_cast<int>(chosen.size()) == count) return chosen;
    choose(bonn::indexOf({double(thetaDeg), double(phiDeg)}));
  }
  while (static_cast<int>(chosen.size()) < count) {
    int best = 0;
    for (int i = 1; i < bonn::kDirectionCount; ++i) {
      // Strictly farther (beyond rounding) wins, so ties keep the lower index; chosen ones sit at
      // distance 0.
      if (nearest[i] > nearest[best] + 1e-12) best = i;
    }
    choose(best);
  }
  return chosen;
}

SliceSet extractUniformSamples(const Abrdf& table, int count) {
  const std::vector<int> directions = farthestPointDirections(count);
  SliceSet samples;
  for (int light : directions) {
    for (int view : directions) {
      const Direction l = bonn::direction(light), v = bonn::direction(view);
      samples.add({SliceKind::Point,
                   {bonn::kRings[bonn::ringOfIndex(light)].thetaDeg,
                    bonn::kRings[bonn::ringOfIndex(view)].thetaDeg}},
                  {l, v, table.at(light, view)});
    }
  }
  return samples;
}

}  // namespace slicecap::recon
