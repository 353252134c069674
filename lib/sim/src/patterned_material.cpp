// The woven pattern of two Ward satins.
#include "slicecap/sim/patterned_material.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "slicecap/sim/sim_error.hpp"

namespace slicecap::sim {
namespace {

class WovenMaterial final : public PatternedMaterial {
 public:
  WovenMaterial(double cellMm, bool finerThanPixels)
      : cellMm_(cellMm),
        finerThanPixels_(finerThanPixels),
        warp_(models::makeWard({0.05, 0.10, 0.32}, {0.18, 0.18, 0.22}, 0.15, 0.40, 0.0)),
        weft_(models::makeWard({0.34, 0.07, 0.05}, {0.20, 0.15, 0.15}, 0.15, 0.40, 90.0)) {}

  const models::ReflectanceModel& component(int index) const override {
    return index == 0 ? *warp_ : *weft_;
  }
  double firstWeightAt(double xMm, double yMm) const override {
    if (finerThanPixels_) return 0.5;
    const auto i = static_cast<long long>(std::floor(xMm / cellMm_));
    const auto j = static_cast<long long>(std::floor(yMm / cellMm_));
    return (i + j) % 2 == 0 ? 1.0 : 0.0;
  }
  // A box's mean of the checkerboard: its x and y stripes are independent over a box, so the
  // fraction of warp is fx fy + (1 - fx)(1 - fy), fx and fy the box's share of even stripes.
  double firstWeightOver(double xMm, double yMm, double halfXMm, double halfYMm) const override {
    if (finerThanPixels_) return 0.5;
    const double fx = evenShare(xMm, halfXMm), fy = evenShare(yMm, halfYMm);
    return fx * fy + (1.0 - fx) * (1.0 - fy);
  }
  Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const override {
    return lerp(warp_->evaluate(toLight, toView), weft_->evaluate(toLight, toView), 0.5);
  }
  std::string describe() const override {
    const std::string layout = finerThanPixels_
                                   ? "threads finer than a pixel (both at every point)"
                                   : "plain weave of " + std::to_string(cellMm_) + " mm cells";
    return "woven: " + layout + ", warp " + warp_->describe() + ", weft " + weft_->describe();
  }
  bool isIsotropic() const override { return false; }

 private:
  // The length of [0, x] (x may be negative: signed) in even stripes (floor(x / cell) even).
  double evenLength(double xMm) const {
    const double period = 2.0 * cellMm_;
    const double periods = std::floor(xMm / period);
    return periods * cellMm_ + std::min(xMm - periods * period, cellMm_);
  }
  // The share of [x - half, x + half] in even stripes; at a point (half 0), the stripe's.
  double evenShare(double xMm, double halfMm) const {
    if (!(halfMm > 1e-9 * cellMm_))
      return static_cast<long long>(std::floor(xMm / cellMm_)) % 2 == 0 ? 1.0 : 0.0;
    return (evenLength(xMm + halfMm) - evenLength(xMm - halfMm)) / (2.0 * halfMm);
  }

  double cellMm_;
  bool finerThanPixels_;
  std::unique_ptr<models::ReflectanceModel> warp_, weft_;
};

}  // namespace

Rgb PatternedMaterial::evaluateAt(double xMm, double yMm, const UnitVector& toLight,
                                  const UnitVector& toView) const {
  const double w = firstWeightAt(xMm, yMm);
  return lerp(component(1).evaluate(toLight, toView), component(0).evaluate(toLight, toView), w);
}

double PatternedMaterial::firstWeightOver(double xMm, double yMm, double, double) const {
  return firstWeightAt(xMm, yMm);
}

std::shared_ptr<const PatternedMaterial> makeWovenMaterial(double cellMm, bool finerThanPixels) {
  if (!(cellMm >= 0.5 && cellMm <= 100.0))
    throw SimError("woven material: cell must be 0.5 to 100 mm, not " +
                   std::to_string(cellMm));
  return std::make_shared<WovenMaterial>(cellMm, finerThanPixels);
}

}  // namespace slicecap::sim
