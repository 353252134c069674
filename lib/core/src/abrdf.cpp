// Tabulating an analytic BRDF on the Bonn grid.
#include "slicecap/core/abrdf.hpp"

#include <array>

namespace slicecap {

Abrdf tabulateOnGrid(const std::function<Rgb(const UnitVector& toLight, const UnitVector& toView)>& brdf) {
  std::array<UnitVector, bonn::kDirectionCount> directions;
  for (int i = 0; i < bonn::kDirectionCount; ++i)
    directions[static_cast<std::size_t>(i)] = toUnitVector(bonn::direction(i));
  Abrdf table;
  for (int l = 0; l < bonn::kDirectionCount; ++l)
    for (int v = 0; v < bonn::kDirectionCount; ++v)
      table.set(l, v, brdf(directions[static_cast<std::size_t>(l)], directions[static_cast<std::size_t>(v)]));
  return table;
}

}  // namespace slicecap
