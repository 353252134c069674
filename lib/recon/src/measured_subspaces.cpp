// Slice-sum (or eq. 5) at the four measured pairs, with one error naming every missing slice.
#include "slicecap/recon/measured_subspaces.hpp"

#include "slicecap/recon/errors.hpp"

namespace slicecap::recon {

std::vector<Subspace> reconstructMeasuredSubspaces(const SliceSet& slices, bool isotropic,
                                                   TorusRule rule, const std::string& methodName) {
  std::string missing;
  for (ElevationPair pair : kMeasuredPairs) {
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      if (isotropic && kind == SliceKind::Axial) continue;
      if (!slices.find({kind, pair}))
        missing += (missing.empty() ? "" : ", ") + toString(SliceId{kind, pair});
    }
  }
  if (!missing.empty()) {
    throw ReconstructionError(
        methodName + " needs every measured slice; missing: " + missing +
        (isotropic ? "" : " (its isotropic form needs the diagonal ones only)"));
  }
  std::vector<Subspace> subspaces;
  for (ElevationPair pair : kMeasuredPairs) {
    const Slice& diagonal = *slices.find({SliceKind::Diagonal, pair});
    subspaces.push_back(
        isotropic ? reconstructIsotropicSubspace(diagonal, rule)
                  : reconstructSubspace(*slices.find({SliceKind::Axial, pair}), diagonal, rule));
  }
  return subspaces;
}

}  // namespace slicecap::recon
