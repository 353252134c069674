// A texel's table as the texture fit sees it: a subset of the light/view pairs, whose geometry is
// computed once for the whole texture, and the check that the table is a BRDF with samples.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fit_data.hpp"
#include "slicecap/core/abrdf.hpp"

namespace slicecap::fit::detail {

struct TexelPair {
  PairGeometry geometry;
  int light = 0, view = 0;
};

/// \brief Every `stride`-th (light, view) pair of the 81 x 81 grid, light-major.
std::vector<TexelPair> strideGeometry(int stride);

/// \brief The fit's domain (as makeFitData) on `pairs` only; the scale M is the whole table's
/// largest cos-weighted value. The table must have a positive value.
FitData texelFitData(const Abrdf& table, const std::vector<TexelPair>& pairs);

/// \brief texelProblem's text for an all-zero table.
inline constexpr const char* kNoSamples =
    "no samples (every value is zero: the reconstruction had nothing for this texel)";

/// \brief Why the table cannot be fitted: kNoSamples, or "not a BRDF: value V at light L, view W,
/// channel C"; nullopt when it can.
std::optional<std::string> texelProblem(const Abrdf& table);

}  // namespace slicecap::fit::detail
