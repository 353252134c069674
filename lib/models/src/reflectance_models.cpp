// The analytic models: Lambert, Ward, anisotropic GGX, Blinn-Phong, the elevation lobe, sheen.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "slicecap/core/angles.hpp"
#include "slicecap/models/model_error.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::models {
namespace {

constexpr double kPi = std::numbers::pi;

std::string rgbText(const Rgb& c) {
  std::ostringstream s;
  s << c.r() << "/" << c.g() << "/" << c.b();
  return s.str();
}

UnitVector halfVector(const UnitVector& l, const UnitVector& v) {
  UnitVector h{l.x + v.x, l.y + v.y, l.z + v.z};
  const double length = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
  return {h.x / length, h.y / length, h.z / length};
}

// A vector expressed in the tangent frame whose x axis lies at azimuth tangentDeg.
struct TangentFrame {
  double cosT, sinT;
  explicit TangentFrame(double tangentDeg)
      : cosT(std::cos(degToRad(tangentDeg))), sinT(std::sin(degToRad(tangentDeg))) {}
  UnitVector toLocal(const UnitVector& w) const {
    return {w.x * cosT + w.y * sinT, -w.x * sinT + w.y * cosT, w.z};
  }
};

void requirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw ModelError(std::string(what) + " must be positive");
}

class Lambert final : public ReflectanceModel {
 public:
  explicit Lambert(const Rgb& albedo) : albedo_(albedo) {}
  Rgb evaluate(const UnitVector&, const UnitVector&) const override {
    return albedo_ * (1.0 / kPi);
  }
  std::string describe() const override { return "lambert albedo=" + rgbText(albedo_); }
  bool isIsotropic() const override { return true; }

 private:
  Rgb albedo_;
};

class Ward final : public ReflectanceModel {
 public:
  Ward(const Rgb& diffuse, const Rgb& specular, double ax, double ay, double tangentDeg)
      : diffuse_(diffuse),
        specular_(specular),
        ax_(ax),
        ay_(ay),
        tangentDeg_(tangentDeg),
        frame_(tangentDeg) {
    requirePositive(ax, "Ward alpha_x");
    requirePositive(ay, "Ward alpha_y");
  }
  Rgb evaluate(const UnitVector& l, const UnitVector& v) const override {
    const UnitVector h = frame_.toLocal(halfVector(l, v));
    const double exponent = -((h.x * h.x) / (ax_ * ax_) + (h.y * h.y) / (ay_ * ay_)) / (h.z * h.z);
    const double lobe = std::exp(exponent) / (4.0 * kPi * ax_ * ay_ * std::sqrt(l.z * v.z));
    return diffuse_ * (1.0 / kPi) + specular_ * lobe;
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "ward diffuse=" << rgbText(diffuse_) << " specular=" << rgbText(specular_) << " ax=" << ax_
      << " ay=" << ay_ << " tangent_deg=" << tangentDeg_;
    return s.str();
  }
  bool isIsotropic() const override { return ax_ == ay_; }

 private:
  Rgb diffuse_, specular_;
  double ax_, ay_, tangentDeg_;
  TangentFrame frame_;
};

class AnisotropicGgx final : public ReflectanceModel {
 public:
  AnisotropicGgx(const Rgb& diffuse, const Rgb& f0, double ax, double ay, double tangentDeg)
      : diffuse_(diffuse), f0_(f0), ax_(ax), ay_(ay), tangentDeg_(tangentDeg), frame_(tangentDeg) {
    requirePositive(ax, "GGX alpha_x");
    requirePositive(ay, "GGX alpha_y");
  }
  Rgb evaluate(const UnitVector& lWorld, const UnitVector& vWorld) const override {
    const UnitVector l = frame_.toLocal(lWorld), v = frame_.toLocal(vWorld);
    const UnitVector h = halfVector(l, v);
    const double s = (h.x * h.x) / (ax_ * ax_) + (h.y * h.y) / (ay_ * ay_) + h.z * h.z;
    const double distribution = 1.0 / (kPi * ax_ * ay_ * s * s);
    const double masking = 1.0 / (1.0 + lambda(l) + lambda(v));
    const double cosLh = std::clamp(l.x * h.x + l.y * h.y + l.z * h.z, 0.0, 1.0);
    const double schlick = std::pow(1.0 - cosLh, 5.0);
    const double common = distribution * masking / (4.0 * l.z * v.z);
    Rgb value = diffuse_ * (1.0 / kPi);
    for (std::size_t c = 0; c < 3; ++c)
      value[c] += (f0_[c] + (1.0 - f0_[c]) * schlick) * common;
    return value;
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "ggx diffuse=" << rgbText(diffuse_) << " f0=" << rgbText(f0_) << " ax=" << ax_
      << " ay=" << ay_ << " tangent_deg=" << tangentDeg_;
    return s.str();
  }
  bool isIsotropic() const override { return ax_ == ay_; }

 private:
  double lambda(const UnitVector& w) const {
    const double t = (ax_ * ax_ * w.x * w.x + ay_ * ay_ * w.y * w.y) / (w.z * w.z);
    return (-1.0 + std::sqrt(1.0 + t)) / 2.0;
  }
  Rgb diffuse_, f0_;
  double ax_, ay_, tangentDeg_;
  TangentFrame frame_;
};

class BlinnPhong final : public ReflectanceModel {
 public:
  BlinnPhong(const Rgb& diffuse, const Rgb& specular, double exponent)
      : diffuse_(diffuse), specular_(specular), exponent_(exponent) {
    requirePositive(exponent, "Blinn-Phong exponent");
  }
  Rgb evaluate(const UnitVector& l, const UnitVector& v) const override {
    const double lobe = (exponent_ + 2.0) / (8.0 * kPi) * std::pow(halfVector(l, v).z, exponent_);
    return diffuse_ * (1.0 / kPi) + specular_ * lobe;
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "blinn-phong diffuse=" << rgbText(diffuse_) << " specular=" << rgbText(specular_)
      << " n=" << exponent_;
    return s.str();
  }
  bool isIsotropic() const override { return true; }

 private:
  Rgb diffuse_, specular_;
  double exponent_;
};

class ElevationLobe final : public ReflectanceModel {
 public:
  ElevationLobe(const Rgb& k, double exponent) : k_(k), exponent_(exponent) {}
  Rgb evaluate(const UnitVector& l, const UnitVector& v) const override {
    return k_ * std::pow(l.z * v.z, exponent_);
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "elevation-lobe k=" << rgbText(k_) << " n=" << exponent_;
    return s.str();
  }
  bool isIsotropic() const override { return true; }

 private:
  Rgb k_;
  double exponent_;
};

class Sheen final : public ReflectanceModel {
 public:
  Sheen(const Rgb& diffuse, const Rgb& sheen, double roughness)
      : diffuse_(diffuse), sheen_(sheen), roughness_(roughness) {
    requirePositive(roughness, "sheen roughness");
  }
  Rgb evaluate(const UnitVector& l, const UnitVector& v) const override {
    const UnitVector h = halfVector(l, v);
    const double sinH = std::sqrt(std::max(0.0, 1.0 - h.z * h.z));
    const double inverseR = 1.0 / roughness_;
    const double distribution = (2.0 + inverseR) * std::pow(sinH, inverseR) / (2.0 * kPi);
    const double visibility = 1.0 / (4.0 * (l.z + v.z - l.z * v.z));
    return diffuse_ * (1.0 / kPi) + sheen_ * (distribution * visibility);
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "sheen diffuse=" << rgbText(diffuse_) << " sheen=" << rgbText(sheen_)
      << " roughness=" << roughness_;
    return s.str();
  }
  bool isIsotropic() const override { return true; }

 private:
  Rgb diffuse_, sheen_;
  double roughness_;
};

}  // namespace

std::unique_ptr<ReflectanceModel> makeLambert(const Rgb& albedo) {
  return std::make_unique<Lambert>(albedo);
}
std::unique_ptr<ReflectanceModel> makeWard(const Rgb& diffuse, const Rgb& specular, double alphaX,
                                           double alphaY, double tangentDeg) {
  return std::make_unique<Ward>(diffuse, specular, alphaX, alphaY, tangentDeg);
}
std::unique_ptr<ReflectanceModel> makeAnisotropicGgx(const Rgb& diffuse, const Rgb& f0,
                                                     double alphaX, double alphaY,
                                                     double tangentDeg) {
  return std::make_unique<AnisotropicGgx>(diffuse, f0, alphaX, alphaY, tangentDeg);
}
std::unique_ptr<ReflectanceModel> makeBlinnPhong(const Rgb& diffuse, const Rgb& specular,
                                                 double exponent) {
  return std::make_unique<BlinnPhong>(diffuse, specular, exponent);
}
std::unique_ptr<ReflectanceModel> makeElevationLobe(const Rgb& k, double exponent) {
  return std::make_unique<ElevationLobe>(k, exponent);
}
std::unique_ptr<ReflectanceModel> makeSheen(const Rgb& diffuse, const Rgb& sheen,
                                            double roughness) {
  return std::make_unique<Sheen>(diffuse, sheen, roughness);
}

Abrdf tabulate(const ReflectanceModel& model) {
  return tabulateOnGrid([&model](const UnitVector& l, const UnitVector& v) { return model.evaluate(l, v); });
}

}  // namespace slicecap::models
