// The built-in named materials, with realistic parameters for common anisotropic surfaces.
#include <stdexcept>

#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::models {
namespace {

// Sum of two models, for layered materials such as velvet with a directional pile.
class SumModel final : public ReflectanceModel {
 public:
  SumModel(std::unique_ptr<ReflectanceModel> a, std::unique_ptr<ReflectanceModel> b)
      : a_(std::move(a)), b_(std::move(b)) {}
  Rgb evaluate(const UnitVector& l, const UnitVector& v) const override {
    return a_->evaluate(l, v) + b_->evaluate(l, v);
  }
  std::string describe() const override { return a_->describe() + " + " + b_->describe(); }
  bool isIsotropic() const override { return a_->isIsotropic() && b_->isIsotropic(); }

 private:
  std::unique_ptr<ReflectanceModel> a_, b_;
};

}  // namespace

std::vector<NamedMaterial> anisotropicMaterials() {
  return {
      {"brushed-aluminium",
       makeAnisotropicGgx({0.02, 0.02, 0.02}, {0.91, 0.92, 0.92}, 0.06, 0.35, 0.0)},
      {"brushed-steel-30",
       makeAnisotropicGgx({0.03, 0.03, 0.03}, {0.56, 0.57, 0.58}, 0.10, 0.40, 30.0)},
      {"brushed-brass-120",
       makeAnisotropicGgx({0.02, 0.02, 0.01}, {0.91, 0.78, 0.42}, 0.20, 0.50, 120.0)},
      {"copper-ggx-15",
       makeAnisotropicGgx({0.02, 0.01, 0.01}, {0.95, 0.64, 0.54}, 0.30, 0.12, 15.0)},
      {"satin-red-90", makeWard({0.35, 0.05, 0.06}, {0.20, 0.16, 0.16}, 0.08, 0.30, 90.0)},
      {"satin-blue-45", makeWard({0.04, 0.08, 0.30}, {0.15, 0.15, 0.18}, 0.12, 0.45, 45.0)},
      {"ward-gold-60", makeWard({0.05, 0.03, 0.01}, {0.50, 0.35, 0.12}, 0.15, 0.05, 60.0)},
      {"velvet-green-20",
       std::make_shared<SumModel>(makeSheen({0.02, 0.12, 0.04}, {0.30, 0.60, 0.35}, 0.35),
                                  makeWard({0.0, 0.0, 0.0}, {0.05, 0.10, 0.06}, 0.30, 0.60, 20.0))},
  };
}

std::vector<NamedMaterial> isotropicMaterials() {
  return {
      {"matte-paint", makeLambert({0.60, 0.55, 0.50})},
      {"blue-plastic", makeBlinnPhong({0.05, 0.10, 0.40}, {0.40, 0.40, 0.40}, 60.0)},
      {"red-plastic-ggx",
       makeAnisotropicGgx({0.50, 0.05, 0.05}, {0.04, 0.04, 0.04}, 0.15, 0.15, 0.0)},
      {"rough-metal", makeAnisotropicGgx({0.0, 0.0, 0.0}, {0.90, 0.90, 0.90}, 0.35, 0.35, 0.0)},
      {"velvet-red", makeSheen({0.15, 0.01, 0.02}, {0.70, 0.15, 0.15}, 0.30)},
  };
}

std::shared_ptr<const ReflectanceModel> findMaterial(const std::string& name) {
  for (auto* list : {anisotropicMaterials, isotropicMaterials}) {
    for (const NamedMaterial& m : list()) {
      if (m.name == name) return m.model;
    }
  }
  return nullptr;
}

}  // namespace slicecap::models
