// Method A (docs/method.md §5): 4-D multiquadric RBF interpolation in the onion parameterisation over
// the four measured subspaces.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/recon/onion.hpp"
#include "slicecap/recon/rbf_interpolant.hpp"
#include "slicecap/recon/slice_sum.hpp"
#include "slicecap/recon/subspace.hpp"

namespace slicecap::recon {

/// \brief One entry of the 81 x 81 table.
struct TableEntry {
  int light = 0;
  int view = 0;
};

/// \brief The entries of the four measured subspaces, in kMeasuredPairs order, each subspace
/// row-major (light azimuth, then view): 1296 entries, the same for every capture.
std::vector<TableEntry> measuredEntries();
/// \brief Every other entry of the table (5265), light-major.
std::vector<TableEntry> unmeasuredEntries();

/// \brief Options of Method A.
struct MethodAParams {
  /// \brief Use only the diagonal slices (eq. 5); the axial ones may then be absent.
  bool isotropic = false;
  TorusRule torusRule = TorusRule::FundamentalSquare;
  OnionFrame frame = OnionFrame::ViewRelative;
  /// \brief [docs/method.md §5.2 defaults kept: multiquadric, r0 = median NN distance, constant term,
  /// linear values. Issue 3 measured every open choice (docs/method.md §5.3): none helps in the
  /// linear domain; absolute frame + r3 + linear term help only with compressed values, which
  /// 5.2 does not list as open, and even then A does not beat uniform in all three metrics.]
  RbfParams rbf;
  /// \brief Returns false, with a reason, for invalid RBF options.
  bool isValid(std::string* error) const { return rbf.isValid(error); }
};

/// \brief Everything of Method A that does not depend on the material: the 1296 centres (the
/// entries of the four measured subspaces, identical for every capture), their factored RBF
/// system, and the evaluation matrix at the other 5265 entries. Build it once (~0.3 s here) and
/// reuse it for every channel, material and texture pixel: a table then costs two triangular
/// solves and one 5265 x 1297 product.
///
/// Memory: the LU factors in double (13.5 MB: the system's condition number is ~6e5, so float
/// would lose digits) and the evaluation matrix in float (27 MB instead of 55 MB in double). The
/// float rows cost at most ~5e-5 of the table's peak (chrome, the largest dynamic range of the
/// shared tables), below 0.2 of a step of the paper's 8-bit encoding.
class MethodASystem {
 public:
  /// \brief Throws ReconArgumentError for invalid RBF options.
  explicit MethodASystem(OnionFrame frame = OnionFrame::ViewRelative, const RbfParams& rbf = {});

  /// \brief The full table from the four measured subspaces (kMeasuredPairs order): their values
  /// are kept, every other entry is interpolated (as v^(1/valueGamma), RbfParams), negatives are
  /// clipped to 0. Throws ReconArgumentError when the subspaces are not the measured pairs in
  /// that order, ReconstructionError when the interpolant is not finite (RBF options for which
  /// the system is singular in floating point).
  Abrdf interpolate(const std::vector<Subspace>& measured, double valueGamma = 1.0) const;

  /// \brief Many tables at once (e.g. texture pixels): centre values, 1296 x k in
  /// centreEntries() order, to the interpolant at otherEntries(), 5265 x k (not clipped).
  Eigen::MatrixXf interpolateOthers(const Eigen::MatrixXd& centreValues) const;

  const std::vector<TableEntry>& centreEntries() const { return centres_; }
  const std::vector<TableEntry>& otherEntries() const { return others_; }
  const RbfInterpolant& interpolant() const { return rbf_; }
  OnionFrame frame() const { return frame_; }
  /// \brief Bytes held by the factorisation and the evaluation matrix.
  std::size_t memoryBytes() const;

 private:
  OnionFrame frame_;
  std::vector<TableEntry> centres_, others_;
  RbfInterpolant rbf_;
  Eigen::MatrixXf evaluation_;  ///< 5265 x 1297
};

/// \brief The system for these options, built on first use and kept for the life of the process
/// (thread-safe). Throws ReconArgumentError for invalid RBF options.
const MethodASystem& sharedMethodASystem(OnionFrame frame = OnionFrame::ViewRelative,
                                         const RbfParams& rbf = {});

/// \brief The 81 x 81 table from the 8 slices (4 diagonal ones when isotropic), with the shared
/// system of the params. Throws ReconstructionError naming every missing slice,
/// ReconArgumentError for invalid params.
Abrdf reconstructMethodA(const SliceSet& slices, const MethodAParams& params = {});

}  // namespace slicecap::recon
