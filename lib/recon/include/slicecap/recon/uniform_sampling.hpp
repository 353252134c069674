// The uniform-sampling baseline's capture (docs/method.md §6.3): n light x n view grid directions.
#pragma once

#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::recon {

/// \brief The paper's baseline size: 13 light x 13 view directions, 169 samples.
inline constexpr int kUniformBaselineDirections = 13;

/// \brief `count` Bonn directions spread over the hemisphere by greedy farthest-point selection
/// on their unit vectors, starting from the pole, in selection order. The first 14 are docs/method.md
/// §6.3's published order (its ties fell by rounding), so 13 gives its list: (0,0), (30,30),
/// (30,270), (45,140), (45,200), (45,340), (60,54), (60,252), (60,288), (75,0), (75,105),
/// (75,165), (75,225); later ties go to the lower index. Throws ReconArgumentError unless
/// 1 <= count <= 81.
std::vector<int> farthestPointDirections(int count);

/// \brief The uniform capture of a table: every pair of the `count` directions as light and as
/// view, `count`^2 point samples (SliceKind::Point) with the table's exact values. Throws
/// ReconArgumentError unless 1 <= count <= 81.
SliceSet extractUniformSamples(const Abrdf& table, int count = kUniformBaselineDirections);

}  // namespace slicecap::recon
