// Offline reconstruction of a session with a missing slice: name it, say how to sweep it, and
// export with the prior.
#include "slicecap/methods/method_fallback.hpp"

#include <algorithm>
#include <stdexcept>

#include "slicecap/recon/errors.hpp"

namespace slicecap::methods {

std::vector<SliceId> missingMeasuredSlices(const SliceSet& slices, bool isotropic) {
  std::vector<SliceId> missing;
  for (ElevationPair pair : kMeasuredPairs)
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      if (isotropic && kind == SliceKind::Axial) continue;
      if (!slices.find({kind, pair})) missing.push_back({kind, pair});
    }
  return missing;
}

std::string sweepCommand(const SliceId& slice) {
  return "slicecap sweep start " + std::string(toString(slice.kind)) + " " +
         std::to_string(slice.elevations.thetaIDeg) + " " +
         std::to_string(slice.elevations.thetaVDeg);
}

MethodRun runMethodOrPrior(const Method& method, const SliceSet& slices,
                           const MethodOptions& options) {
  const bool anySubset = methodInfo(method.id).reads != SliceSubset::EveryMeasuredSlice;
  const std::vector<SliceId> missing = missingMeasuredSlices(slices, options.isotropic);
  if (anySubset || missing.empty()) return method.run(slices, options);
  std::string which;
  for (const SliceId& slice : missing)
    which += "\n  " + toString(slice) + ": " + sweepCommand(slice);
  const std::string lacks = "method " + method.name + " needs every measured slice; missing:" +
                            which;
  // Every diagonal slice and no axial one: an isotropic capture (--isotropic), not a lost slice;
  // the prior would hide that mistake.
  const bool allAxial = std::all_of(missing.begin(), missing.end(), [](const SliceId& s) {
    return s.kind == SliceKind::Axial;
  });
  if (!options.isotropic && allAxial && missing.size() == kMeasuredPairs.size())
    throw recon::ReconstructionError(
        lacks + "\nonly the diagonal slices were measured: an isotropic material reconstructs "
                "from them with --isotropic; else sweep the axial ones, or use --method prior");
  MethodRun run;
  try {
    // The cells' reading stays the cells' (b-cells falls back to prior-cells).
    run = findMethod(priorOfSameReading(method.id)).run(slices, options);
  } catch (const std::exception& error) {
    throw recon::ReconstructionError(lacks + "\n(and the prior, which reads any subset, failed: " +
                                     error.what() + ")");
  }
  run.warnings.insert(run.warnings.begin(),
                      lacks + "\nexported with the prior instead (it reads any subset of slices)");
  run.details["method_requested"] = method.name;
  run.details["missing_slices"] = nlohmann::json::array();
  for (const SliceId& slice : missing)
    run.details["missing_slices"].push_back(
        {{"slice", toString(slice)}, {"command", sweepCommand(slice)}});
  return run;
}

}  // namespace slicecap::methods
