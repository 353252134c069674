// Tone curves: validation, the tabulated standard curves, and exact piecewise-linear inversion.
#include "slicecap/core/tone_curve.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slicecap/core/core_error.hpp"

namespace slicecap {
namespace {

double interpolate(const std::vector<std::pair<double, double>>& points, double x, bool forward) {
  x = std::clamp(x, 0.0, 1.0);
  const auto key = [forward](const std::pair<double, double>& p) {
    return forward ? p.first : p.second;
  };
  const auto value = [forward](const std::pair<double, double>& p) {
    return forward ? p.second : p.first;
  };
  const auto upper = std::upper_bound(points.begin(), points.end(), x,
                                      [&](double v, const auto& p) { return v < key(p); });
  if (upper == points.end()) return value(points.back());
  if (upper == points.begin()) return value(points.front());
  const auto& a = *(upper - 1);
  const auto& b = *upper;
  const double t = (x - key(a)) / (key(b) - key(a));
  return value(a) + t * (value(b) - value(a));
}

double srgbEncode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

}  // namespace

ToneCurve::ToneCurve(std::string name, std::vector<std::pair<double, double>> points)
    : name_(std::move(name)), points_(std::move(points)) {
  const auto fail = [this](const std::string& why) {
    throw CoreError("tone curve '" + name_ + "': " + why);
  };
  if (points_.size() < 2) fail("needs at least two points");
  if (points_.front() != std::pair<double, double>{0.0, 0.0})
    fail("must start at (0, 0)");
  if (points_.back() != std::pair<double, double>{1.0, 1.0}) fail("must end at (1, 1)");
  for (std::size_t i = 1; i < points_.size(); ++i)
    if (!(points_[i].first > points_[i - 1].first) || !(points_[i].second > points_[i - 1].second))
      fail("point " + std::to_string(i) + " (" + std::to_string(points_[i].first) + ", " +
           std::to_string(points_[i].second) + ") does not rise above the one before");
}

ToneCurve ToneCurve::srgb() {
  // Denser near black, where the curve bends most: 1e-4 of full scale at worst.
  std::vector<std::pair<double, double>> points{{0.0, 0.0}};
  for (int i = 1; i <= 1024; ++i) {
    const double linear = std::pow(i / 1024.0, 2.0);
    points.emplace_back(linear, srgbEncode(linear));
  }
  points.back() = {1.0, 1.0};
  return ToneCurve("srgb", std::move(points));
}

ToneCurve ToneCurve::linear() {
  return ToneCurve("linear", {{0.0, 0.0}, {1.0, 1.0}});
}

ToneCurve ToneCurve::imx708Tuning() {
  static constexpr int kTable[][2] = {
      {0, 0},         {1024, 5040},   {2048, 9338},   {3072, 12356},  {4096, 15312},
      {5120, 18051},  {6144, 20790},  {7168, 23193},  {8192, 25744},  {9216, 27942},
      {10240, 30035}, {11264, 32005}, {12288, 33975}, {13312, 35815}, {14336, 37600},
      {15360, 39168}, {16384, 40642}, {18432, 43379}, {20480, 45749}, {22528, 47753},
      {24576, 49621}, {26624, 51253}, {28672, 52698}, {30720, 53796}, {32768, 54876},
      {36864, 57012}, {40960, 58656}, {45056, 59954}, {49152, 61183}, {53248, 62355},
      {57344, 63419}, {61440, 64476}, {65535, 65535}};
  std::vector<std::pair<double, double>> points;
  for (const auto& [in, out] : kTable) points.emplace_back(in / 65535.0, out / 65535.0);
  return ToneCurve("imx708-tuning", std::move(points));
}

double ToneCurve::encode(double linearValue) const {
  return interpolate(points_, linearValue, true);
}

double ToneCurve::decode(double encoded) const {
  return interpolate(points_, encoded, false);
}

}  // namespace slicecap
