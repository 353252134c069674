// The method registry: each method is one entry here.
#include "slicecap/cli/methods.hpp"

#include "slicecap/cli/args.hpp"
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

}  // namespace

const std::vector<Method>& reconstructionMethods() {
  static const std::vector<Method> methods{
      {"b",
       "Method B of the paper (METHOD.md 4): slice-sum subspaces, lobe-weighted elevation blends",
       runMethodB},
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
