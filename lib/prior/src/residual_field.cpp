// The residual field: slice sums in the log domain at measured pairs, carried to the others.
#include "residual_field.hpp"

#include <array>
#include <optional>
#include <stdexcept>

#include "slicecap/prior/prior_model.hpp"
#include "slicecap/recon/slice_sum.hpp"
#include "slicecap/recon/subspace.hpp"

namespace slicecap::prior {
namespace {

using recon::PeriodicSignal;
using recon::Subspace;

constexpr std::array<int, 6> kElevationsDeg{0, 15, 30, 45, 60, 75};

// Where the axial line (phi_v = phi_i + 15) crosses the diagonal line (phi_i = -phi_v): u* of the
// two crossings on the torus, and w* of the axial line.
constexpr double kCrossingAxialDeg = 172.5;
constexpr double kCrossingDiagonalDeg = 187.5;

Subspace measuredBlock(ElevationPair pair, const PeriodicSignal* axial,
                       const PeriodicSignal* diagonal) {
  Subspace block(pair);
  Rgb crossing;
  if (axial && diagonal) {
    const Rgb onAxial =
        lerp(axial->at(kCrossingAxialDeg), axial->at(kCrossingAxialDeg + 180.0), 0.5);
    crossing = lerp(onAxial, diagonal->at(kCrossingDiagonalDeg), 0.5);
  }
  std::size_t axialCursor = 0, diagonalCursor = 0;  // along a ring the positions come in order
  for (int p = 0; p < block.lightRing().count; ++p) {
    for (int q = 0; q < block.viewRing().count; ++q) {
      const recon::SliceCoordinates x =
          recon::sliceCoordinates(block.lightRing().azimuthDeg(p), block.viewRing().azimuthDeg(q));
      Rgb value = Rgb{} - crossing;
      if (axial) value += axial->at(x.axialDeg, axialCursor);
      if (diagonal) value += diagonal->at(x.diagonalDeg, diagonalCursor);
      block.at(p, q) = value;
    }
  }
  return block;
}

// The block at `targetDeg` along a line from the known blocks of that line (by elevation):
// linear between the nearest known elevations around it, the nearest one held outside them.
template <typename Resample, typename ResampledBlend>
std::optional<Subspace> alongLine(const std::map<int, Subspace>& known, int targetDeg,
                                  Resample resample, ResampledBlend resampledBlend) {
  if (known.empty()) return std::nullopt;
  auto above = known.lower_bound(targetDeg);
  if (above == known.end()) return resample(std::prev(above)->second, targetDeg);
  if (above->first == targetDeg) return above->second;
  if (above == known.begin()) return resample(above->second, targetDeg);
  auto below = std::prev(above);
  const double t = double(targetDeg - below->first) / double(above->first - below->first);
  return resampledBlend(below->second, above->second, t, targetDeg);
}

}  // namespace

void addResidualField(const SliceResiduals& residuals, Eigen::Ref<Eigen::MatrixXf> logTable) {
  if (logTable.rows() != 81 * 81 || logTable.cols() != 3)
    throw PriorError("residual field: the log table must be 6561 x 3");
  std::map<ElevationPair, std::optional<PeriodicSignal>[2]> signals;
  for (const auto& [id, points] : residuals) {
    if (points.empty()) continue;
    signals[id.elevations][id.kind == SliceKind::Axial ? 0 : 1].emplace(points);
  }
  // Step 1: at each light elevation with measured pairs, every view elevation.
  std::map<int, std::map<int, Subspace>> byLight;  // theta_i -> theta_v -> block
  for (const auto& [pair, s] : signals) {
    byLight[pair.thetaIDeg].emplace(
        pair.thetaVDeg, measuredBlock(pair, s[0] ? &*s[0] : nullptr, s[1] ? &*s[1] : nullptr));
  }
  std::map<int, std::map<int, Subspace>> byView;  // theta_v -> theta_i -> block
  for (const auto& [thetaIDeg, line] : byLight) {
    for (int thetaVDeg : kElevationsDeg) {
      auto block = alongLine(
          line, thetaVDeg, [](const Subspace& s, int to) { return s.resampledToViewElevation(to); },
          Subspace::blendAtViewElevation);
      if (block) byView[thetaVDeg].emplace(thetaIDeg, std::move(*block));
    }
  }
  // Step 2: at every view elevation, every light elevation.
  for (const auto& [thetaVDeg, line] : byView) {
    for (int thetaIDeg : kElevationsDeg) {
      auto block = alongLine(
          line, thetaIDeg,
          [](const Subspace& s, int to) { return s.resampledToLightElevation(to); },
          Subspace::blendAtLightElevation);
      if (!block) continue;
      for (int p = 0; p < block->lightRing().count; ++p) {
        for (int q = 0; q < block->viewRing().count; ++q) {
          const int entry = block->lightRing().index(p) * 81 + block->viewRing().index(q);
          for (int c = 0; c < 3; ++c)
            logTable(entry, c) += static_cast<float>(block->at(p, q)[c]);
        }
      }
    }
  }
}

}  // namespace slicecap::prior
