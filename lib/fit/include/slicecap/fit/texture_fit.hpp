// Fitting the parametric material to every texel of a BTF (SVBRDF maps, docs/material-fit.md
// "Texture mode"): texels in parallel, each warm-started from its neighbour's solution.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::fit {

/// \brief Fills `tables` (resized to the texture's resolution) with row `row`'s texel tables,
/// column 0 first. Called from several threads at once for distinct rows.
using TexelRowReader = std::function<void(int row, std::vector<Abrdf>& tables)>;

/// \brief What became of one texel.
enum class TexelStatus {
  Fitted,       ///< a converged fit
  NoSamples,    ///< an all-zero table: the reconstruction had no samples for it
  NotABrdf,     ///< a negative or non-finite value
  NotConverged  ///< neither the warm start nor the multi-start fit converged
};

/// \brief "fitted", "no samples", "not a BRDF", "not converged".
std::string_view toString(TexelStatus status);

/// \brief What became of a fitted texel's shading-normal tilt (docs/material-fit.md "Texture
/// mode", "The normal map").
enum class TiltStatus {
  Fitted,  ///< the tilt was fitted with the lobe (it may be flat: the data said so)
  NoLobe,  ///< flat: the specular lobe is too weak to locate (f0 ~ 0 or alphas ~ 1)
  Off      ///< flat: TextureFitOptions::fitTilt was false
};

/// \brief "fitted", "flat: no specular lobe to tilt", "flat: tilt fitting off".
std::string_view toString(TiltStatus status);

struct TexelFit {
  TexelStatus status = TexelStatus::NotConverged;
  FittedMaterial material;     ///< canonical; meaningless unless status is Fitted
  double rmseLevels = 0.0;     ///< RMS residual on the fit's pairs, 8-bit sRGB levels
  bool multiStart = false;     ///< the warm start was poor (or there was none): multi-start fit
  std::string problem;         ///< why it is not Fitted, starting with "texel (x,y)"
  /// \brief The shading normal in the texel's frame (x = azimuth 0, z = the surface normal):
  /// the lobe and the diffuse cosine are evaluated with light and view in the frame it tilts, the
  /// tangent (`material.tangentDeg`, measured in the untilted plane) projected onto its plane.
  /// (0, 0, 1) unless `tilt` is Fitted.
  UnitVector shadingNormal;
  TiltStatus tilt = TiltStatus::Off;
};

struct TextureFitOptions {
  int threads = 2;          ///< rows fitted at once (>= 1)
  int maxIterations = 200;  ///< Levenberg-Marquardt iterations per solve
  /// \brief The warm-started solve sees every this-many-th light/view pair (coprime with 81, so
  /// that every light and view direction is seen): 938 pairs still pin 12 parameters, and the
  /// solve's time is proportional to the pairs (docs/material-fit.md, "Texture mode").
  int pairStride = 7;
  /// \brief A warm start is kept when it converged and its RMS residual is at most this factor
  /// times its neighbour's, or at most `warmAcceptFloorLevels`; otherwise the texel gets the
  /// multi-start fit (fitMaterial's four tangent starts, GGX only), and the better of the two.
  double warmAcceptFactor = 1.5;
  double warmAcceptFloorLevels = 1.0;
  /// \brief A warm-started solve has converged when an iteration changes the cost by less than
  /// this fraction.
  double functionTolerance = 1e-6;
  /// \brief Levenberg-Marquardt's first step bound for a warm start (Ceres' default, 1e4, is for
  /// a start far from the solution; from a neighbour's, bold first steps are rejected and retried:
  /// 1 cut the woven BTF's fit time by a third, docs/results/2026-12-02-svbrdf-maps.md).
  double warmTrustRegionRadius = 1.0;
  /// \brief Fit each texel's shading-normal tilt with its lobe (two more parameters); false
  /// gives flat normals and the fit as it was before the normal map (for comparison).
  bool fitTilt = true;
};

struct TextureFitResult {
  int resolution = 0;
  std::vector<TexelFit> texels;  ///< row-major, texel (x, y) at y * resolution + x
  std::size_t fitted = 0, multiStart = 0;
  std::size_t tiltFitted = 0;  ///< fitted texels whose tilt is Fitted (the rest flat, named)
  double seconds = 0.0;  ///< wall-clock time of the fit
  int threads = 0;
};

/// \brief Fits diffuse + anisotropic GGX (no sheen: see docs/material-fit.md) with a tilted
/// shading normal to every texel.
/// Column 0 is fitted first, top to bottom, each texel warm-started from the one above (texel
/// (0,0) by the multi-start fit); then rows are shared out among the threads, each texel
/// warm-started from its left neighbour. A texel that cannot be fitted is named in its
/// TexelFit::problem, never given a default material; the next texel then starts from the last
/// good solution. A texel whose specular lobe is too weak to locate gets a flat normal and
/// TiltStatus::NoLobe (its other parameters refitted flat). Throws FitArgumentError for
/// resolution < 1 or options out of range; exceptions of `readRow` (e.g. io::IoError) pass through.
TextureFitResult fitTexture(int resolution, const TexelRowReader& readRow,
                            const TextureFitOptions& options = {});

}  // namespace slicecap::fit
