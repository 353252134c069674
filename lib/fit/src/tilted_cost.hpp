// The texture fit's least-squares cost with a tilted shading normal: MaterialCost's residuals with
// the GGX lobe and the diffuse cosine evaluated in the tilted frame (tilted_lobe.hpp).
#pragma once

#include <ceres/cost_function.h>

#include "fit_data.hpp"

namespace slicecap::fit::detail {

/// \brief Parameter block of the tilt: the shading normal's x and y in the texel's frame
/// (z = +sqrt(1 - x^2 - y^2)).
inline constexpr int kTiltParameters = 2;

/// \brief All residuals of MaterialCost (no sheen) with the tilt: parameter blocks {ggx (10),
/// tilt (2)}. As MaterialCost, the colours' derivatives are written out and Jets carry only the
/// lobe shape (alphas, tangent, tilt: five wide).
class TiltedCost final : public ceres::CostFunction {
 public:
  explicit TiltedCost(const FitData& data);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const FitData& data_;
};

}  // namespace slicecap::fit::detail
