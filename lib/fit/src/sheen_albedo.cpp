// The directional albedo table of KHR_materials_sheen's lobe (sheen_albedo.hpp says how it is
// integrated and why).
#include "slicecap/fit/sheen_albedo.hpp"

#include <numbers>

namespace slicecap::fit {
namespace {

constexpr int kThetaSteps = 64, kPhiSteps = 64;
constexpr double kMinimumCosine = 1e-3;

double charlieDistribution(double cosH, double alpha) {
  const double sin2h = std::max(1.0 - cosH * cosH, 0.0);
  return (2.0 + 1.0 / alpha) * std::pow(sin2h, 0.5 / alpha) / (2.0 * std::numbers::pi);
}

double albedoAt(double mu, double alpha) {
  const double pi = std::numbers::pi;
  const double sinV = std::sqrt(1.0 - mu * mu);
  const double lambdaV = detail::charlieLambda(mu, alpha);
  double sum = 0.0;
  for (int t = 0; t < kThetaSteps; ++t) {
    const double theta = (t + 0.5) * (pi / 2) / kThetaSteps;
    const double cosL = std::cos(theta), sinL = std::sin(theta);
    const double visibility =
        1.0 / ((1.0 + lambdaV + detail::charlieLambda(cosL, alpha)) * (4.0 * mu * cosL));
    for (int p = 0; p < kPhiSteps; ++p) {
      const double phi = (p + 0.5) * pi / kPhiSteps;
      // h = (l + v) / |l + v|, v = (sinV, 0, mu), l = (sinL cos phi, sinL sin phi, cosL).
      const double hx = sinL * std::cos(phi) + sinV, hy = sinL * std::sin(phi), hz = cosL + mu;
      const double cosH = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
      sum += charlieDistribution(cosH, alpha) * visibility * cosL * sinL;
    }
  }
  return 2.0 * sum * (pi / 2 / kThetaSteps) * (pi / kPhiSteps);
}

SheenAlbedoTable makeTable() {
  SheenAlbedoTable table{};
  constexpr double step =
      (kSheenAlbedoMaxRoughness - kSheenAlbedoMinRoughness) / (kSheenAlbedoRoughnesses - 1);
  for (int j = 0; j < kSheenAlbedoRoughnesses; ++j) {
    const double alpha = kSheenAlbedoMinRoughness + j * step;
    for (int i = 0; i < kSheenAlbedoCosines; ++i) {
      const double mu = std::max(static_cast<double>(i) / (kSheenAlbedoCosines - 1), kMinimumCosine);
      table[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)] = albedoAt(mu, alpha);
    }
  }
  return table;
}

}  // namespace

const SheenAlbedoTable& sheenAlbedoTable() {
  static const SheenAlbedoTable table = makeTable();
  return table;
}

}  // namespace slicecap::fit
