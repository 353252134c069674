// The halfway method: the unmeasured entries borrowed from the measured ones nearest in halfway
// and difference angles, where reflectance varies slowly (an improvement over Methods A and B).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/recon/method_a.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_sum.hpp"
#include "slicecap/recon/subspace.hpp"

namespace slicecap::recon {

/// \brief Options of the halfway method. The defaults were chosen on a third of the shared tables
/// and the analytic anisotropic materials (docs/method.md §7).
struct HalfwayParams {
  /// \brief Use only the diagonal slices (eq. 5); the axial ones may then be absent.
  bool isotropic = false;
  TorusRule torusRule = TorusRule::FundamentalSquare;
  /// \brief A capture whose axialVariation() is below this is treated as isotropic (eq. 5, and
  /// Method B's blends between 30 and 75 deg); negative: never.
  double isotropyThreshold = 0.03;
  /// \brief How many measured entries each unmeasured one is borrowed from (>= 1).
  int neighbours = 3;
  /// \brief Weight of the difference angle against the halfway vector in the neighbour distance
  /// (>= 0): small, because Fresnel and shadowing change slowly with it.
  double differenceWeight = 0.3;
  /// \brief Exponent p of the foreshortening carried over: the specular part is moved as
  /// f (cos theta_i cos theta_v)^p (p = 1: a microfacet lobe's D F G / 4).
  double foreshorteningExponent = 1.0;
  /// \brief The neighbours are averaged as v^(1/valueGamma) (> 0), as a-gamma interpolates: a
  /// geometric-leaning mean that keeps a narrow highlight from spreading at full height.
  double valueGamma = 2.2;
  /// \brief Returns false, with a reason, for options out of range.
  bool isValid(std::string* error) const;
};

/// \brief Everything of the halfway method that does not depend on the material: for each of the
/// 5265 unmeasured entries, its nearest measured entries (distance: the halfway vectors in the
/// material's frame, or their elevations only when `isotropic`, plus the weighted difference
/// angle) and their inverse-distance weights. Built once per options (~20 ms CPU here), ~150 kB.
class HalfwaySystem {
 public:
  /// \brief Throws ReconArgumentError for invalid params.
  explicit HalfwaySystem(const HalfwayParams& params);

  /// \brief The full table from the four measured subspaces (kMeasuredPairs order): their values
  /// are kept; every other entry is a diffuse floor (each channel's 2nd percentile of the measured
  /// values) plus the weighted specular remainder of its neighbours (averaged as v^(1/gamma)),
  /// moved by the foreshortening ratio. Throws ReconArgumentError when the subspaces are not the
  /// measured pairs in order.
  Abrdf interpolate(const std::vector<Subspace>& measured) const;

  const std::vector<TableEntry>& otherEntries() const { return others_; }

 private:
  struct Tap {
    int centre = 0;
    float weight = 0.0f;
  };
  HalfwayParams params_;
  std::vector<TableEntry> centres_, others_;
  std::vector<Tap> taps_;           ///< neighbours per other entry, consecutive
  std::vector<float> centreScale_;  ///< (cos theta_i cos theta_v)^p of each centre
  std::vector<float> otherScale_;   ///< its inverse at each other entry
};

/// \brief The system for these options (the torus rule and threshold aside), built on first use
/// and kept for the life of the process (thread-safe). Throws ReconArgumentError for invalid
/// params.
const HalfwaySystem& sharedHalfwaySystem(const HalfwayParams& params);

/// \brief How far the axial slices are from constant: the largest, over the axial slices, of the
/// coefficient of variation (standard deviation / mean) of their samples' RGB means. An axial
/// slice keeps phi_v - phi_i at 15 deg, so an isotropic material gives a constant; nullopt when
/// no axial slice has a positive mean.
std::optional<double> axialVariation(const SliceSet& slices);

/// \brief What the halfway method decided, for the CLI and tests.
struct HalfwayReport {
  std::optional<double> axialVariation;
  bool treatedIsotropic = false;
  MethodBReport methodB;  ///< the fits of the Method B part (isotropic materials only)
};

/// \brief The 81 x 81 table from the 8 slices (4 diagonal ones when isotropic). An isotropic
/// capture (params.isotropic, or an axialVariation below the threshold) keeps Method B (eq. 5) for
/// every pair with both elevations in [30, 75] deg or both 15 deg and borrows the rest, where
/// Method B extrapolates, from the halfway neighbours; an anisotropic capture borrows every
/// unmeasured entry, because its highlight moves with the elevations and Method B's scalar blends
/// cannot move it. Throws ReconstructionError naming every missing slice,
/// ReconArgumentError for invalid params.
Abrdf reconstructHalfway(const SliceSet& slices, const HalfwayParams& params = {},
                         HalfwayReport* report = nullptr);

}  // namespace slicecap::recon
