// Method B (docs/method.md §4): slice-sum at the measured pairs, model-weighted blends for the rest.
#pragma once

#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/recon/lafortune_fit.hpp"
#include "slicecap/recon/slice_sum.hpp"

namespace slicecap::recon {

/// \brief Options of Method B.
struct MethodBParams {
  /// \brief Use only the diagonal slices (eq. 5); the axial ones may then be absent.
  bool isotropic = false;
  TorusRule torusRule = TorusRule::FundamentalSquare;
  LobeFitParams fit;
};

/// \brief One lobe fit of the two interpolation steps.
struct LineFit {
  std::string line;  ///< e.g. "views at theta_i 30" or "lights at theta_v 45"
  LobeFitResult fit;
  bool usedClosedForm = false;  ///< Ceres did not converge; the closed form was used instead
};

/// \brief What Method B did: the fits and their convergence, for the CLI and tests.
struct MethodBReport {
  std::vector<LineFit> fits;
  bool allConverged() const;
};

/// \brief The 81 x 81 table from the 8 slices (4 diagonal ones when isotropic). Throws
/// ReconstructionError naming every missing slice. Negative results are clipped to 0.
Abrdf reconstructMethodB(const SliceSet& slices, const MethodBParams& params = {},
                         MethodBReport* report = nullptr);

}  // namespace slicecap::recon
