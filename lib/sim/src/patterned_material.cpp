// The woven pattern of two Ward satins.
#include "slicecap/sim/patterned_material.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "slicecap/sim/sim_error.hpp"

namespace slicecap::sim {
namespace {

class WovenMaterial final : public PatternedMaterial {
 public:
  explicit WovenMaterial(double cellMm)
      : cellMm_(cellMm),
        warp_(models::makeWard({0.05, 0.10, 0.32}, {0.18, 0.18, 0.22}, 0.15, 0.40, 0.0)),
        weft_(models::makeWard({0.34, 0.07, 0.05}, {0.20, 0.15, 0.15}, 0.15, 0.40, 90.0)) {}

  const models::ReflectanceModel& component(int index) const override {
    return index == 0 ? *warp_ : *weft_;
  }
  double firstWeightAt(double xMm, double yMm) const override {
    const auto i = static_cast<long long>(std::floor(xMm / cellMm_));
    const auto j = static_cast<long long>(std::floor(yMm / cellMm_));
    return (i + j) % 2 == 0 ? 1.0 : 0.0;
  }
  Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const override {
    return lerp(warp_->evaluate(toLight, toView), weft_->evaluate(toLight, toView), 0.5);
  }
  std::string describe() const override {
    return "woven: plain weave of " + std::to_string(cellMm_) + " mm cells, warp " +
           warp_->describe() + ", weft " + weft_->describe();
  }
  bool isIsotropic() const override { return false; }

 private:
  double cellMm_;
  std::unique_ptr<models::ReflectanceModel> warp_, weft_;
};

}  // namespace

Rgb PatternedMaterial::evaluateAt(double xMm, double yMm, const UnitVector& toLight,
                                  const UnitVector& toView) const {
  const double w = firstWeightAt(xMm, yMm);
  return lerp(component(1).evaluate(toLight, toView), component(0).evaluate(toLight, toView), w);
}

std::shared_ptr<const PatternedMaterial> makeWovenMaterial(double cellMm) {
  if (!(cellMm >= 0.5 && cellMm <= 100.0))
    throw SimError("woven material: cell must be 0.5 to 100 mm, not " +
                   std::to_string(cellMm));
  return std::make_shared<WovenMaterial>(cellMm);
}

}  // namespace slicecap::sim
