// 8-bit paper metrics: cos-weighting, reference normalisation, sRGB, CIE76 dE, RMSE, PSNR.
#include "slicecap/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slicecap/core/grid.hpp"
#include "slicecap/eval/eval_error.hpp"

namespace slicecap::eval {
namespace {

struct Lab {
  double l, a, b;
};

double labF(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

Lab toLab(const std::array<unsigned char, 3>& srgb8) {
  double rgb[3];
  for (int c = 0; c < 3; ++c)
    rgb[c] = srgbDecode(srgb8[c] / 255.0);
  // sRGB (D65) to XYZ; the white point is the XYZ of sRGB white (1, 1, 1).
  const double x = 0.4124564 * rgb[0] + 0.3575761 * rgb[1] + 0.1804375 * rgb[2];
  const double y = 0.2126729 * rgb[0] + 0.7151522 * rgb[1] + 0.0721750 * rgb[2];
  const double z = 0.0193339 * rgb[0] + 0.1191920 * rgb[1] + 0.9503041 * rgb[2];
  constexpr double xw = 0.4124564 + 0.3575761 + 0.1804375;
  constexpr double yw = 0.2126729 + 0.7151522 + 0.0721750;
  constexpr double zw = 0.0193339 + 0.1191920 + 0.9503041;
  const double fx = labF(x / xw), fy = labF(y / yw), fz = labF(z / zw);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

}  // namespace

double srgbEncode(double linear) {
  if (linear <= 0.0031308) return 12.92 * linear;
  return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double srgbDecode(double encoded) {
  if (encoded <= 0.04045) return encoded / 12.92;
  return std::pow((encoded + 0.055) / 1.055, 2.4);
}

double deltaE76(const std::array<unsigned char, 3>& a, const std::array<unsigned char, 3>& b) {
  const Lab la = toLab(a), lb = toLab(b);
  return std::sqrt((la.l - lb.l) * (la.l - lb.l) + (la.a - lb.a) * (la.a - lb.a) +
                   (la.b - lb.b) * (la.b - lb.b));
}

double cosWeightedMaximum(const Abrdf& table) {
  const auto& cosines = bonn::cosines();
  double maximum = 0.0;
  for (int l = 0; l < Abrdf::kDirections; ++l) {
    for (int v = 0; v < Abrdf::kDirections; ++v) {
      maximum = std::max(maximum, table.at(l, v).maxChannel() * cosines[l]);
    }
  }
  return maximum;
}

std::array<unsigned char, Abrdf::kValueCount> encodePaper8Bit(const Abrdf& table,
                                                              double referenceMax) {
  const auto& cosines = bonn::cosines();
  std::array<unsigned char, Abrdf::kValueCount> out{};
  const auto values = table.values();
  for (std::size_t i = 0; i < values.size(); ++i) {
    const int light = static_cast<int>(i / (3 * Abrdf::kDirections));
    const double normalised = std::clamp(values[i] * cosines[light] / referenceMax, 0.0, 1.0);
    out[i] = static_cast<unsigned char>(std::lround(srgbEncode(normalised) * 255.0));
  }
  return out;
}

bool canCompareAgainst(const Abrdf& reference) { return cosWeightedMaximum(reference) > 0.0; }

Metrics compare(const Abrdf& reference, const Abrdf& test) {
  const double referenceMax = cosWeightedMaximum(reference);
  if (!(referenceMax > 0.0)) throw EvalError("reference table has no positive value");
  const auto ref8 = encodePaper8Bit(reference, referenceMax);
  const auto test8 = encodePaper8Bit(test, referenceMax);

  Metrics m;
  double squared = 0.0;
  for (std::size_t i = 0; i < ref8.size(); ++i) {
    const double d = double(ref8[i]) - double(test8[i]);
    squared += d * d;
  }
  m.rmse = std::sqrt(squared / double(ref8.size()));
  m.psnrDb = m.rmse > 0.0 ? std::min(kMaxPsnrDb, 20.0 * std::log10(255.0 / m.rmse)) : kMaxPsnrDb;

  double deltaSum = 0.0;
  for (std::size_t p = 0; p < ref8.size(); p += 3) {
    deltaSum +=
        deltaE76({ref8[p], ref8[p + 1], ref8[p + 2]}, {test8[p], test8[p + 1], test8[p + 2]});
  }
  m.deltaE = deltaSum / double(ref8.size() / 3);

  double differenceSquared = 0.0, referenceSquared = 0.0;
  for (std::size_t i = 0; i < reference.values().size(); ++i) {
    const double r = reference.values()[i], t = test.values()[i];
    differenceSquared += (t - r) * (t - r);
    referenceSquared += r * r;
  }
  m.relativeRmse = std::sqrt(differenceSquared / referenceSquared);
  const auto& ref = reference.values();
  const auto& tst = test.values();
  m.peakRatio = *std::max_element(tst.begin(), tst.end()) / *std::max_element(ref.begin(), ref.end());
  return m;
}

}  // namespace slicecap::eval
