// Frames of a diagonal 75/75 sweep with window cells along the slice, valued by a profile and a
// print at each cell's spot: the pass-again and texture-verdict tests' synthetic sweeps.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::test {

/// \brief A value along the slice parameter (deg): a diffuse floor and lobes.
using Profile = std::function<double(double)>;
/// \brief The material's albedo at cell k's spot (cells -4 to 4 across the window; plain: 1).
using Print = std::function<double(int)>;

/// \brief A Gaussian lobe of height 10 along the slice parameter.
inline double lobe(double parameterDeg, double centreDeg, double sigmaDeg) {
  const double d = parameterDeg - centreDeg;
  return 10.0 * std::exp(-d * d / (2.0 * sigmaDeg * sigmaDeg));
}

/// \brief A 75/75 diagonal frame at slice parameter `centreDeg` whose window holds 9 cells from
/// 3.2 deg before to 3.2 deg after it (0.8 deg apart, as on the default target), valued by
/// `profile` times `print` at the cell's spot, variance 1e-4.
inline capture::FrameSample diagonalFrameAt(double centreDeg, const Profile& profile,
                                            std::uint64_t index,
                                            const Print& print = [](int) { return 1.0; }) {
  auto point = [](double p) {
    const AzimuthPair a = slicePoint(SliceKind::Diagonal, p);
    return std::pair{Direction{75, a.phiIDeg}, Direction{75, a.phiVDeg}};
  };
  const auto [light, view] = point(centreDeg);
  capture::FrameSample s{std::int64_t(index) * 33000, index, light, view,
                         Rgb::gray(profile(centreDeg))};
  capture::WindowCells cells;
  cells.cellsPerSide = 3;  // the rules read the cells' directions, not the grid
  for (int k = -4; k <= 4; ++k) {
    const auto [cellLight, cellView] = point(centreDeg + 0.8 * k);
    cells.cells.push_back({cellLight, cellView, Rgb::gray(profile(centreDeg + 0.8 * k) * print(k)),
                           Rgb::gray(1e-4), false});
  }
  s.cells = std::move(cells);
  return s;
}

/// \brief diagonalFrameAt's frame as the rig makes it, for a journal that keeps only the geometry
/// (placeCellDirections): the LED and the camera 300 mm from the window centre, an 8 x 8 grid over
/// the 33 mm read of the default window; cell (i, j) (row, column) valued by `profile` at its own
/// slice parameter times `print(i, j)`.
inline capture::FrameSample placedDiagonalFrameAt(double centreDeg, const Profile& profile,
                                                  std::uint64_t index,
                                                  const std::function<double(int, int)>& print) {
  const AzimuthPair a = slicePoint(SliceKind::Diagonal, centreDeg);
  const Direction light{75, a.phiIDeg}, view{75, a.phiVDeg};
  auto pointAt = [](const Direction& d) {
    const UnitVector u = toUnitVector(d);
    return std::array<double, 3>{300.0 * u.x, 300.0 * u.y, 300.0 * u.z};
  };
  capture::FrameSample s{std::int64_t(index) * 33000, index, light, view,
                         Rgb::gray(profile(centreDeg))};
  capture::WindowCells cells;
  cells.cellsPerSide = 8;
  cells.gridMm = {-16.5, -16.5, 16.5, 16.5};
  cells.lightMm = pointAt(light);
  cells.cameraMm = pointAt(view);
  cells.cells.resize(64);
  capture::placeCellDirections(cells);
  for (int k = 0; k < 64; ++k) {
    capture::CellSample& cell = cells.cells[std::size_t(k)];
    double parameter = sliceParameterDeg(SliceKind::Diagonal, {cell.light, cell.view, {}});
    // The cell's parameter near the frame's, not a turn away.
    parameter += 360.0 * std::round((centreDeg - parameter) / 360.0);
    cell.value = Rgb::gray(profile(parameter) * print(k / 8, k % 8));
    cell.variance = Rgb::gray(1e-6);
  }
  s.cells = std::move(cells);
  return s;
}

/// \brief diagonalFrameAt's frames every 3 deg over [fromDeg, toDeg], but those whose centre
/// lies in a skipped range, numbered from 1.
inline std::vector<capture::FrameSample> diagonalSweep(
    const Profile& profile, double fromDeg, double toDeg,
    const std::vector<std::pair<double, double>>& skipped,
    const Print& print = [](int) { return 1.0; }) {
  std::vector<capture::FrameSample> frames;
  std::uint64_t index = 0;
  for (double p = fromDeg; p <= toDeg; p += 3.0) {
    bool skip = false;
    for (const auto& [a, b] : skipped) skip = skip || (p > a && p < b);
    if (!skip) frames.push_back(diagonalFrameAt(p, profile, ++index, print));
  }
  return frames;
}

}  // namespace slicecap::test
