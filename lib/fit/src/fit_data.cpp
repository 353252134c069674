// The fit's domain: the paper's 8-bit convention (eval::encodePaper8Bit) without the rounding.
#include "fit_data.hpp"

#include "slicecap/eval/metrics.hpp"

namespace slicecap::fit::detail {

FitData makeFitData(const Abrdf& table) {
  const double maximum = eval::cosWeightedMaximum(table);
  const auto& cosines = bonn::cosines();
  std::array<UnitVector, bonn::kDirectionCount> directions;
  for (int d = 0; d < bonn::kDirectionCount; ++d)
    directions[static_cast<std::size_t>(d)] = toUnitVector(bonn::direction(d));
  FitData data;
  const std::size_t count = std::size_t{bonn::kDirectionCount} * bonn::kDirectionCount;
  data.pairs.reserve(count);
  data.scale.reserve(count);
  data.target.reserve(count);
  for (int l = 0; l < bonn::kDirectionCount; ++l) {
    for (int v = 0; v < bonn::kDirectionCount; ++v) {
      const auto li = static_cast<std::size_t>(l), vi = static_cast<std::size_t>(v);
      data.pairs.push_back(pairGeometry(directions[li], directions[vi]));
      const double scale = cosines[li] / maximum;
      data.scale.push_back(scale);
      const Rgb value = table.at(l, v);
      data.target.push_back({255.0 * srgbCurve(value[0] * scale), 255.0 * srgbCurve(value[1] * scale),
                             255.0 * srgbCurve(value[2] * scale)});
    }
  }
  return data;
}

FitData everyNthPair(const FitData& data, int stride) {
  FitData subset;
  for (std::size_t i = 0; i < data.pairs.size(); i += static_cast<std::size_t>(stride)) {
    subset.pairs.push_back(data.pairs[i]);
    subset.scale.push_back(data.scale[i]);
    subset.target.push_back(data.target[i]);
  }
  return subset;
}

}  // namespace slicecap::fit::detail
