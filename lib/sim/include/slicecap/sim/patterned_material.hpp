// A material that varies over the window: two analytic materials in a pattern (the virtual rig's
// texture, for BTF capture).
#pragma once

#include <memory>

#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::sim {

/// \brief Two materials laid out over the window: at a target point (mm, target frame) a fraction
/// of the first and the rest of the second. As a ReflectanceModel it is the window's area mean
/// (what the average sample and the truth of the window centre see); the renderer shades it pixel
/// by pixel.
class PatternedMaterial : public models::ReflectanceModel {
 public:
  /// \brief Component 0 or 1.
  virtual const models::ReflectanceModel& component(int index) const = 0;
  /// \brief The fraction of component 0 at a target point, in [0, 1].
  virtual double firstWeightAt(double xMm, double yMm) const = 0;
  /// \brief The fraction of component 0 over the box of half-widths halfXMm, halfYMm (>= 0),
  /// sides along the target's axes, about a target point. A pixel integrates the light over its
  /// area; read at its centre alone, a pattern near or finer than a pixel's footprint (a fine
  /// weave, foreshortened at a grazing view) aliases into each pixel being all of one thread,
  /// which no sensor does. The renderer reads a pixel's footprint (a parallelogram) as 3 x 3
  /// such boxes. This default reads the centre; a pattern overrides it with its area mean.
  virtual double firstWeightOver(double xMm, double yMm, double halfXMm, double halfYMm) const;
  /// \brief The BRDF at a target point.
  Rgb evaluateAt(double xMm, double yMm, const UnitVector& toLight, const UnitVector& toView) const;
};

/// \brief A plain weave of square cells of `cellMm` (a cell corner at the window centre): warp
/// cells, (i + j) even, are a blue anisotropic Ward satin with its tangent along x; weft cells a
/// red one along y. The window mean is their average. `finerThanPixels`: the same two threads
/// mixed half and half at every point, as a weave far finer than a pixel reads (no pattern at any
/// cell or pixel, the analytic lobes shaded as they are): the plain counterpart a weave's capture
/// is compared with. Throws SimError unless 0.5 <= cellMm <= 100.
std::shared_ptr<const PatternedMaterial> makeWovenMaterial(double cellMm = 10.0,
                                                           bool finerThanPixels = false);

}  // namespace slicecap::sim
