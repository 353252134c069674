// The method registry: each method is one entry here.
#include "slicecap/cli/methods.hpp"

#include "slicecap/cli/args.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/method_b.hpp"

namespace slicecap::cli {
namespace {

MethodRun runMethodB(const SliceSet& slices, const MethodOptions& options) {
  recon::MethodBParams params;
  params.isotropic = options.isotropic;
  params.torusRule = options.torusRule;
  recon::MethodBReport report;
  MethodRun run{recon::reconstructMethodB(slices, params, &report),
                options.isotropic ? "B-isotropic" : "B",
                {},
                {},
                {}};
  run.details["all_fits_converged"] = report.allConverged();
  for (const recon::LineFit& f : report.fits) {
    run.details["fits"].push_back({{"line", f.line},
                                   {"k", f.fit.lobe.k},
                                   {"n", f.fit.lobe.n},
                                   {"converged", f.fit.converged},
                                   {"closed_form_fallback", f.usedClosedForm},
                                   {"iterations", f.fit.iterations}});
    run.lines.push_back("lobe fit, " + f.line + ": n = " + std::to_string(f.fit.lobe.n) +
                        (f.fit.converged ? "" : "  (Ceres did not converge; closed form used)"));
  }
  if (!report.allConverged())
    run.warnings.push_back("some lobe fits did not converge; their closed form was used");
  return run;
}

MethodRun runPrior(const SliceSet& slices, const MethodOptions& options) {
  prior::PriorParams params;
  params.isotropicOnly = options.isotropic;
  prior::PriorReport report;
  MethodRun run{prior::reconstructWithPrior(slices, prior::defaultPriorModel(), params, &report),
                options.isotropic ? "prior-isotropic" : "prior",
                {},
                {},
                {}};
  nlohmann::json pairs = nlohmann::json::array();
  for (ElevationPair p : report.measuredPairs)
    pairs.push_back(std::to_string(p.thetaIDeg) + "/" + std::to_string(p.thetaVDeg));
  run.details["prior"] = {{"file", prior::locatePriorModel().string()},
                          {"measured_pairs", pairs},
                          {"anisotropy_terms", report.anisotropyTermsUsed},
                          {"isotropic_gcv", report.isotropicScore},
                          {"anisotropic_gcv", report.anisotropicScore},
                          {"fit_rms_log", report.fitRmsLog}};
  run.lines.push_back("prior fit: RMS log residual " + std::to_string(report.fitRmsLog) +
                      (report.anisotropyTermsUsed ? "; half-vector anisotropy terms used"
                                                  : "; isotropic fit"));
  if (report.measuredPairs.size() < kMeasuredPairs.size())
    run.warnings.push_back("only " + std::to_string(report.measuredPairs.size()) +
                           " elevation pairs measured; the others come from the prior alone");
  return run;
}

}  // namespace

const std::vector<Method>& reconstructionMethods() {
  static const std::vector<Method> methods{
      {"b",
       "Method B of the paper (METHOD.md 4): slice-sum subspaces, lobe-weighted elevation blends",
       runMethodB},
      {"prior",
       "learned prior (issue 10): PCA of measured tables fitted at the samples' actual angles, "
       "half-vector anisotropy, measured slices kept; any subset of slices",
       runPrior},
  };
  return methods;
}

const Method& findMethod(const std::string& name) {
  for (const Method& m : reconstructionMethods()) {
    if (m.name == name) return m;
  }
  throw UsageError("unknown method '" + name + "' (known: " + methodNames() + ")");
}

std::string methodNames() {
  std::string names;
  for (const Method& m : reconstructionMethods())
    names += (names.empty() ? "" : ", ") + m.name;
  return names;
}

}  // namespace slicecap::cli
