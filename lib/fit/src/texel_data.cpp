// The texture fit's per-texel data; the geometry is shared, only the targets are per texel.
#include "texel_data.hpp"

#include <cmath>
#include <sstream>

#include "slicecap/eval/metrics.hpp"

namespace slicecap::fit::detail {

std::vector<TexelPair> strideGeometry(int stride) {
  std::array<UnitVector, bonn::kDirectionCount> directions;
  for (int d = 0; d < bonn::kDirectionCount; ++d)
    directions[static_cast<std::size_t>(d)] = toUnitVector(bonn::direction(d));
  std::vector<TexelPair> pairs;
  const int count = bonn::kDirectionCount * bonn::kDirectionCount;
  for (int i = 0; i < count; i += stride) {
    const int l = i / bonn::kDirectionCount, v = i % bonn::kDirectionCount;
    pairs.push_back({pairGeometry(directions[static_cast<std::size_t>(l)],
                                  directions[static_cast<std::size_t>(v)]),
                     l, v});
  }
  return pairs;
}

FitData texelFitData(const Abrdf& table, const std::vector<TexelPair>& pairs) {
  const double maximum = eval::cosWeightedMaximum(table);
  const auto& cosines = bonn::cosines();
  FitData data;
  data.pairs.reserve(pairs.size());
  data.scale.reserve(pairs.size());
  data.target.reserve(pairs.size());
  for (const TexelPair& pair : pairs) {
    data.pairs.push_back(pair.geometry);
    const double scale = cosines[static_cast<std::size_t>(pair.light)] / maximum;
    data.scale.push_back(scale);
    const Rgb value = table.at(pair.light, pair.view);
    data.target.push_back({255.0 * srgbCurve(value[0] * scale), 255.0 * srgbCurve(value[1] * scale),
                           255.0 * srgbCurve(value[2] * scale)});
  }
  return data;
}

std::optional<std::string> texelProblem(const Abrdf& table) {
  bool anyPositive = false;
  for (int l = 0; l < Abrdf::kDirections; ++l)
    for (int v = 0; v < Abrdf::kDirections; ++v)
      for (int c = 0; c < 3; ++c) {
        const float value = table.channel(l, v, c);
        if (!std::isfinite(value) || value < 0.0f) {
          std::ostringstream message;
          message << "not a BRDF: value " << value << " at light " << l << ", view " << v
                  << ", channel " << "RGB"[c];
          return message.str();
        }
        anyPositive = anyPositive || value > 0.0f;
      }
  if (!anyPositive) return std::string(kNoSamples);
  return std::nullopt;
}

}  // namespace slicecap::fit::detail
