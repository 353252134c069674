// Residuals w (255 g(f cos_i / M) - target) with a tilted shading normal (w fades pairs near the
// tilted horizon out), derivatives chained by hand through g and the linear colours; Jets only for
// the lobe shape, the tilt and w.
#include "tilted_cost.hpp"

#include <ceres/jet.h>

#include <cmath>
#include <numbers>

#include "tilted_lobe.hpp"

namespace slicecap::fit::detail {
namespace {

using Jet5 = ceres::Jet<double, 5>;  // log alpha_t, log alpha_b, tangent, normal x, normal y

}  // namespace

TiltedCost::TiltedCost(const FitData& data) : data_(data) {
  set_num_residuals(data.residualCount());
  mutable_parameter_block_sizes()->assign({kGgxParameters, kTiltParameters});
}

bool TiltedCost::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
  const double* ggx = parameters[0];
  const double* tilt = parameters[1];
  double* ggxJacobian = jacobians ? jacobians[0] : nullptr;
  double* tiltJacobian = jacobians ? jacobians[1] : nullptr;
  const bool derivatives = ggxJacobian != nullptr || tiltJacobian != nullptr;

  const Jet5 alphaT = exp(Jet5(ggx[6], 0)), alphaB = exp(Jet5(ggx[7], 1));
  const Jet5 tangent(ggx[8], 2), nx(tilt[0], 3), ny(tilt[1], 4);
  const TiltedFrame<Jet5> frame = tiltedFrame(Jet5(cos(tangent)), Jet5(sin(tangent)), nx, ny);
  const double alphaTValue = std::exp(ggx[6]), alphaBValue = std::exp(ggx[7]);
  const TiltedFrame<double> frameValue =
      tiltedFrame(std::cos(ggx[8]), std::sin(ggx[8]), tilt[0], tilt[1]);

  for (std::size_t i = 0; i < data_.pairs.size(); ++i) {
    const PairGeometry& g = data_.pairs[i];
    TiltedShape<Jet5> shape;
    if (derivatives) {
      shape = tiltedShape(g, alphaT, alphaB, frame);
    } else {
      const TiltedShape<double> plain = tiltedShape(g, alphaTValue, alphaBValue, frameValue);
      shape = {Jet5(plain.diffuse), Jet5(plain.specular), Jet5(plain.weight)};
    }
    for (int c = 0; c < 3; ++c) {
      const double fresnel = ggx[3 + c] + (ggx[9] - ggx[3 + c]) * g.fresnelWeight;
      const double diffuse = ggx[c] / std::numbers::pi;
      const double value = diffuse * shape.diffuse.a + fresnel * shape.specular.a;
      const double x = value * data_.scale[i];
      const std::size_t row = 3 * i + static_cast<std::size_t>(c);
      const double curve = srgbCurve(x);
      const double difference = 255.0 * curve - data_.target[i][static_cast<std::size_t>(c)];
      const double weight = shape.weight.a;
      residuals[row] = weight * difference;
      if (!derivatives) continue;
      // d residual / d value
      const double k = weight * 255.0 * srgbSlope(x, curve) * data_.scale[i];
      const auto shapeSlope = [&](int p) {
        return k * (diffuse * shape.diffuse.v[p] + fresnel * shape.specular.v[p]) +
               difference * shape.weight.v[p];
      };
      if (ggxJacobian) {
        double* r = ggxJacobian + row * kGgxParameters;
        for (int p = 0; p < kGgxParameters; ++p)
          r[p] = 0.0;
        r[c] = k * shape.diffuse.a / std::numbers::pi;
        r[3 + c] = k * (1.0 - g.fresnelWeight) * shape.specular.a;
        for (int p = 0; p < 3; ++p)
          r[6 + p] = shapeSlope(p);
        r[9] = k * g.fresnelWeight * shape.specular.a;
      }
      if (tiltJacobian) {
        double* r = tiltJacobian + row * kTiltParameters;
        r[0] = shapeSlope(3);
        r[1] = shapeSlope(4);
      }
    }
  }
  return std::isfinite(residuals[0]);
}

}  // namespace slicecap::fit::detail
