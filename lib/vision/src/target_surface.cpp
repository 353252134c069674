// Point sampling and supersampled rasters of the target.
#include "slicecap/vision/target_surface.hpp"

#include <cmath>
#include <stdexcept>

#include "slicecap/vision/vision_error.hpp"

namespace slicecap::vision {

TargetSurface::TargetSurface(TargetGeometry target) : target_(std::move(target)) {
  for (const Marker& m : target_.markers) {
    const PointMm& o = m.cornersMm[0];
    const double scale = kTagBorderCells / (m.sizeMm * m.sizeMm);
    MarkerFrame frame{o,
                      {(m.cornersMm[1].xMm - o.xMm) * scale, (m.cornersMm[1].yMm - o.yMm) * scale},
                      {(m.cornersMm[3].xMm - o.xMm) * scale, (m.cornersMm[3].yMm - o.yMm) * scale},
                      {},
                      tag36h11Bitmap(m.id)};
    const double quiet = m.sizeMm / kTagBorderCells * 1.5;  // 1 cell and rotation slack
    const PointMm c = m.centre();
    const double reach = m.sizeMm / std::sqrt(2.0) + quiet;
    frame.bounds = {c.xMm - reach, c.yMm - reach, c.xMm + reach, c.yMm + reach};
    markers_.push_back(frame);
  }
}

SurfacePoint TargetSurface::at(double xMm, double yMm) const {
  if (!target_.sheet.contains(xMm, yMm)) return {SurfacePoint::Kind::OffSheet, {}};
  if (target_.window.contains(xMm, yMm)) return {SurfacePoint::Kind::Window, {}};
  for (const MarkerFrame& m : markers_) {
    if (!m.bounds.contains(xMm, yMm)) continue;
    const double dx = xMm - m.origin.xMm, dy = yMm - m.origin.yMm;
    const double u = dx * m.uAxis.xMm + dy * m.uAxis.yMm;
    const double v = dx * m.vAxis.xMm + dy * m.vAxis.yMm;
    if (u < -1.0 || v < -1.0 || u >= kTagBorderCells + 1 || v >= kTagBorderCells + 1) continue;
    const int column = static_cast<int>(std::floor(u)) + 1;
    const int rowFromTop = kTagBorderCells - static_cast<int>(std::floor(v));
    return {SurfacePoint::Kind::Printed,
            m.bitmap[rowFromTop][column] ? target_.paperAlbedo : target_.inkAlbedo};
  }
  for (const Patch& p : target_.patches) {
    if (p.rect.contains(xMm, yMm)) return {SurfacePoint::Kind::Printed, p.albedo};
  }
  return {SurfacePoint::Kind::Printed, target_.paperAlbedo};
}

TargetRaster rasterizeTarget(const TargetSurface& surface, const RectMm& area, double pixelsPerMm,
                             int supersample) {
  if (!(pixelsPerMm > 0.0) || supersample < 1)
    throw VisionError("rasterizeTarget: density and supersampling must be positive");
  if (!(area.widthMm() > 0.0 && area.heightMm() > 0.0))
    throw VisionError("rasterizeTarget: empty area");
  TargetRaster raster;
  raster.area = area;
  raster.pixelsPerMm = pixelsPerMm;
  raster.width = static_cast<int>(std::ceil(area.widthMm() * pixelsPerMm - 1e-9));
  raster.height = static_cast<int>(std::ceil(area.heightMm() * pixelsPerMm - 1e-9));
  const std::size_t count = std::size_t(raster.width) * raster.height;
  raster.albedo.assign(count * 3, 0.0f);
  raster.window.assign(count, 0.0f);
  raster.sheet.assign(count, 0.0f);
  const double weight = 1.0 / (supersample * supersample);
  for (int row = 0; row < raster.height; ++row) {
    for (int column = 0; column < raster.width; ++column) {
      Rgb albedo;
      double window = 0.0, sheet = 0.0;
      for (int sy = 0; sy < supersample; ++sy) {
        for (int sx = 0; sx < supersample; ++sx) {
          const double x = area.xMinMm + (column + (sx + 0.5) / supersample) / pixelsPerMm;
          const double y = area.yMaxMm - (row + (sy + 0.5) / supersample) / pixelsPerMm;
          const SurfacePoint point = surface.at(x, y);
          if (point.kind == SurfacePoint::Kind::OffSheet) continue;
          sheet += weight;
          if (point.kind == SurfacePoint::Kind::Window) {
            window += weight;
          } else {
            albedo += point.albedo * weight;
          }
        }
      }
      const std::size_t i = std::size_t(row) * raster.width + column;
      for (int c = 0; c < 3; ++c)
        raster.albedo[3 * i + c] = static_cast<float>(albedo[c]);
      raster.window[i] = static_cast<float>(window);
      raster.sheet[i] = static_cast<float>(sheet);
    }
  }
  return raster;
}

}  // namespace slicecap::vision
