// The window of an accepted frame read as cells (docs/method.md §9, "Window cells"): each cell's
// radiance less the room light, over the point-light model's irradiance at the cell's centre.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "frame_pipeline_state.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/core/grid.hpp"

namespace slicecap::capture {
namespace {

// Millimetres on the target that move a point of the window by at least one pixel in any
// direction: 1 / the smaller singular value of the projection's Jacobian at the window centre
// (foreshortened 4 x across the view at 75 deg). Nullopt when the centre does not project.
std::optional<double> mmPerPixel(const vision::Pose& pose, const vision::CameraModel& camera,
                                 const vision::PointMm& centre) {
  const auto at = [&](double dx, double dy) {
    return camera.project(pose.toCamera({centre.xMm + dx, centre.yMm + dy, 0.0}));
  };
  const auto c = at(0, 0), x = at(1, 0), y = at(0, 1);
  if (!c || !x || !y) return std::nullopt;
  Eigen::Matrix2d jacobian;
  jacobian.col(0) = *x - *c;
  jacobian.col(1) = *y - *c;
  const Eigen::Vector2d eigen =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(jacobian.transpose() * jacobian)
          .eigenvalues();
  if (!(eigen.minCoeff() > 0.0)) return std::nullopt;
  return 1.0 / std::sqrt(eigen.minCoeff());
}

}  // namespace

std::optional<WindowCells> FramePipeline::State::readWindowCells(
    const hal::Frame& frame, const vision::Pose& pose, const std::vector<AmbientTerm>& roomLight,
    const PointLight& light, const Direction& sampleLight) const {
  const int n = settings.windowCellsPerSide;
  const vision::RectMm& w = target.window;
  const std::optional<double> mmPerPx = mmPerPixel(pose, camera, w.centre());
  if (n < 1 || !mmPerPx) return std::nullopt;
  // The window's pixels near its outline mix in the band round it (blur, the pose's error), as
  // a white reference's do: the same inset in pixels, at this pose, whichever way the window is
  // foreshortened.
  const double insetMm = std::min(settings.windowCellInsetPx * *mmPerPx,
                                  0.25 * std::min(w.widthMm(), w.heightMm()));
  WindowCells out;
  out.cellsPerSide = n;
  out.gridMm = {w.xMinMm + insetMm, w.yMinMm + insetMm, w.xMaxMm - insetMm, w.yMaxMm - insetMm};
  // The LED where the sample's light direction points (the fitted one, or the nominal one when
  // the fit's direction is uncertain, as for the window centre), at the fitted distance: each
  // cell's light direction then follows from its own point, as a texel's does (method.md §10).
  const UnitVector toLight = toUnitVector(sampleLight);
  const auto& p = light.positionMm;
  const double distanceMm = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
  out.lightMm = {toLight.x * distanceMm, toLight.y * distanceMm, toLight.z * distanceMm};
  const Eigen::Vector3d cameraCentre = pose.cameraCentreMm();
  out.cameraMm = {cameraCentre.x(), cameraCentre.y(), cameraCentre.z()};
  const double cellW = (out.gridMm[2] - out.gridMm[0]) / n;
  const double cellH = (out.gridMm[3] - out.gridMm[1]) / n;
  for (int k = 0; k < n * n; ++k) {
    const double x0 = out.gridMm[0] + (k % n) * cellW, y0 = out.gridMm[1] + (k / n) * cellH;
    const AreaSpec spec{{x0, y0, x0 + cellW, y0 + cellH}, 0.0, settings.clipFraction};
    const AreaReading area = readArea(frame, pose, camera, spec, settings.noise, *codes);
    const AreaReading room = ambientAt(roomLight, spec, pose);
    const auto [cx, cy] = cellCentreMm(out, k);
    const Rgb irradiance = light.irradianceAt({cx, cy, 0.0});
    CellSample cell;
    cell.clipped = area.clipped || !area.inside;
    for (int c = 0; c < 3; ++c) {
      const double e = irradiance[c];
      // Clamped at 0 as the window centre's sample is; the variance as read.
      const double value = e > 0 ? std::max(0.0, area.mean[c] - room.mean[c]) / e : 0.0;
      const double variance = e > 0 ? (area.variance[c] + room.variance[c]) / (e * e) : 0.0;
      cell.value[c] = cellPrecision(area.inside ? value : 0.0);
      cell.variance[c] = cellPrecision(area.inside ? variance : 0.0);
    }
    out.cells.push_back(cell);
  }
  placeCellDirections(out);
  return out;
}

}  // namespace slicecap::capture
