// One bounded Levenberg-Marquardt solve of the fit from one start, and the Jacobian at a solution.
#pragma once

#include <array>
#include <string>

#include <Eigen/Core>
#include <ceres/solver.h>

#include "bounded_solve.hpp"
#include "fit_data.hpp"

namespace slicecap::fit::detail {

/// \brief The parameters of one solve: the GGX block always, the sheen block when `withSheen`, the
/// coat block when `withCoat`.
/// `isotropic`: the solve keeps the two alphas equal (their logs start equal and move together)
/// and the tangent where it starts, so the lobe has one roughness and no direction.
struct FitParameters {
  std::array<double, kGgxParameters> ggx{};
  std::array<double, kSheenParameters> sheen{};
  std::array<double, kCoatParameters> coat{};
  bool withSheen = false;
  bool withCoat = false;
  bool isotropic = false;
  SheenForm sheenForm = SheenForm::Khr;  ///< how the sheen block joins the base
  int count() const {
    return kGgxParameters + (withSheen ? kSheenParameters : 0) + (withCoat ? kCoatParameters : 0);
  }
  /// \brief Index of the coat block's first parameter among all of count().
  int coatOffset() const { return kGgxParameters + (withSheen ? kSheenParameters : 0); }
};

struct SolveOutcome {
  FitParameters parameters;
  bool converged = false;  ///< Ceres ended with CONVERGENCE and a finite cost
  double cost = 0.0;       ///< 1/2 sum of squared residuals
  int iterations = 0;
  std::string message;     ///< Ceres' own account of how it ended
};

/// \brief Solves from `start` (bounds: albedo and sheen >= 0, sheen <= 1 in the khr form, f0 and f90 in [0, 1], alphas in
/// [0.002, 2], sheen roughness in [0.05, 1], coat weight in [0, 1], coat alpha in [0.002, 2]). Converged: the cost's relative change in an
/// iteration fell below `functionTolerance`. `initialTrustRegionRadius` is Levenberg-Marquardt's
/// first step bound (Ceres' default 1e4: a start far from the solution). Never throws for a bad
/// fit: see `converged`.
SolveOutcome solveFromStart(const FitData& data, const FitParameters& start, int maxIterations,
                            double functionTolerance = 1e-7,
                            double initialTrustRegionRadius = 1e4);

/// \brief solveFromStart's bounds and directions of motion for a GGX parameter block `ggx` (the
/// texture fit's tilted solve shares them). `isotropic`: the two log alphas move together (ggx[7]
/// is set to ggx[6]) and the tangent stays.
BoundedBlock ggxBlock(double* ggx, bool isotropic);

/// \brief The options every fit's Levenberg-Marquardt solve runs with (one thread, silent).
ceres::Solver::Options solverOptions(int maxIterations, double functionTolerance,
                                     double initialTrustRegionRadius);

/// \brief The residuals' Jacobian (residuals x parameters) at `parameters`, over every parameter
/// of the blocks (an isotropic solve's alphas and tangent too, as if free).
Eigen::MatrixXd jacobianAt(const FitData& data, const FitParameters& parameters);

}  // namespace slicecap::fit::detail
