// The fit's least-squares cost with its Jacobian written out: the colours enter linearly, so only
// the lobe shapes need derivatives (three Jet dimensions for the GGX shape, one for the sheen's).
#pragma once

#include <ceres/cost_function.h>

#include "fit_data.hpp"

namespace slicecap::fit::detail {

/// \brief All residuals of the fit in one cost: parameter blocks {ggx (10)}, then sheen (4) when
/// `withSheen`, then coat (2) when `withCoat`, in that order; the sheen joins the base as
/// `sheenForm` says (FittedMaterial::evaluate's formula).
///
/// Why not ceres::AutoDiffCostFunction over fitResiduals: with 9 or 13 Jet dimensions every
/// operation of every pair and channel carries 13 derivatives, although 10 of the parameters are
/// colours whose derivatives are the lobe values themselves. Here the Jets are 3 and 1 wide and
/// are evaluated once a pair, not once a channel: the sheen fit went from ~40 to ~10 ms an
/// iteration, which is what brings one table's fit under a second.
class MaterialCost final : public ceres::CostFunction {
 public:
  MaterialCost(const FitData& data, bool withSheen, bool withCoat = false,
               SheenForm sheenForm = SheenForm::Khr);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const FitData& data_;
  bool withSheen_;
  bool withCoat_;
  SheenForm sheenForm_;
};

}  // namespace slicecap::fit::detail
