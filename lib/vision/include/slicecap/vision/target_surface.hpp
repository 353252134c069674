// What the printed target shows at any point of its plane, and rasters of it (print, simulation).
#pragma once

#include <vector>

#include "slicecap/core/rgb.hpp"
#include "slicecap/vision/tag_family.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::vision {

/// \brief One point of the target plane: off the sheet, in the window, or printed (with albedo).
struct SurfacePoint {
  enum class Kind { OffSheet, Window, Printed };
  Kind kind = Kind::OffSheet;
  Rgb albedo;  ///< for Printed: the paper, a patch's or the ink's albedo
};

/// \brief Point queries of a target; keeps the markers' bitmaps. Markers may have any rotation:
/// each is drawn on the square its corners span.
class TargetSurface {
 public:
  explicit TargetSurface(TargetGeometry target);
  const TargetGeometry& target() const { return target_; }
  /// \brief What the target shows at (x, y) mm: the window first, then the black cells of a
  /// marker, then a patch, then paper.
  SurfacePoint at(double xMm, double yMm) const;

 private:
  // A marker's cell coordinates: u = (p - origin) . uAxis, v = (p - origin) . vAxis in border
  // cells (0..8) from its bottom-left corner; bounds includes the quiet zone, for a quick reject.
  struct MarkerFrame {
    PointMm origin, uAxis, vAxis;
    RectMm bounds;
    TagBitmap bitmap;
  };
  TargetGeometry target_;
  std::vector<MarkerFrame> markers_;
};

/// \brief A raster of an area of the target plane, box-filtered by supersampling: row 0 at the top
/// (largest y), pixel (i, j) covers [xMin + i / ppm, xMin + (i + 1) / ppm) and the rows likewise.
struct TargetRaster {
  RectMm area;
  double pixelsPerMm = 0.0;
  int width = 0;
  int height = 0;
  std::vector<float> albedo;  ///< linear RGB, 3 a pixel, times the printed fraction of the pixel
  std::vector<float> window;  ///< fraction of the pixel that is window (0..1)
  std::vector<float> sheet;   ///< fraction of the pixel on the sheet (0..1)
};

/// \brief Rasterises `area` at `pixelsPerMm` with `supersample` x `supersample` point samples a
/// pixel. Throws VisionError for a non-positive density or an empty area.
TargetRaster rasterizeTarget(const TargetSurface& surface, const RectMm& area, double pixelsPerMm,
                             int supersample = 4);

}  // namespace slicecap::vision
