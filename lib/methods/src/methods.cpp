// The methods' runs: each MethodId's reconstruction and what it reports.
#include "slicecap/methods/methods.hpp"

#include <algorithm>
#include <cstdio>

#include "slicecap/methods/errors.hpp"
#include "slicecap/methods/rbf_spec.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/halfway_method.hpp"
#include "slicecap/recon/method_a.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/scattered_rbf.hpp"

namespace slicecap::methods {
namespace {

MethodRun runMethodBAs(MethodId id, const SliceSet& slices, const MethodOptions& options) {
  recon::MethodBParams params;
  params.isotropic = options.isotropic;
  params.torusRule = options.torusRule;
  recon::MethodBReport report;
  MethodRun run{recon::reconstructMethodB(slices, params, &report),
                exrMethodValue(id, options.isotropic),
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

MethodRun runMethodB(const SliceSet& slices, const MethodOptions& options) {
  return runMethodBAs(MethodId::B, slices, options);
}

// Method B on each bin's value from the window cells nearest the bin centre (docs/method.md §9);
// a slice without cell samples (a CSV, a journal from before cells) keeps its window centres.
// What a run on the cells' reading says about it: how many slices had cells.
void sayCellReading(const SliceSet& slices, MethodRun& run) {
  std::size_t fromCells = 0;
  for (const Slice& s : slices.slices())
    fromCells += s.cellSamples.empty() ? 0 : 1;
  run.details["slices_from_cells"] = fromCells;
  run.lines.push_back(std::to_string(fromCells) + " of " + std::to_string(slices.slices().size()) +
                      " slices valued from the window cells nearest each bin centre");
  if (fromCells < slices.slices().size())
    run.warnings.push_back(std::to_string(slices.slices().size() - fromCells) +
                           " slices have no window cells (a slice CSV, or frames recorded "
                           "before cells were kept): their window centres are used");
}

MethodRun runMethodBCells(const SliceSet& slices, const MethodOptions& options) {
  static_assert(readsCellSamples(MethodId::BCells));
  MethodRun run = runMethodBAs(MethodId::BCells, slices.cellReading(), options);
  sayCellReading(slices, run);
  return run;
}

// The paper interpolated 8-bit sRGB data (docs/method.md §6.2); 2.2 is close to that encoding.
constexpr double kPaperValueGamma = 2.2;

MethodRun runMethodAWithGamma(const SliceSet& slices, const MethodOptions& options,
                              double valueGamma) {
  recon::MethodAParams params;
  params.isotropic = options.isotropic;
  params.torusRule = options.torusRule;
  params.frame = options.onionFrame;
  params.rbf = options.rbf;
  params.rbf.valueGamma = valueGamma;
  const MethodId id = valueGamma == 1.0 ? MethodId::A : MethodId::AGamma;
  MethodRun run{recon::reconstructMethodA(slices, params), exrMethodValue(id, options.isotropic),
                {},
                {},
                {}};
  MethodOptions used = options;
  used.rbf.valueGamma = valueGamma;
  run.details["value_gamma"] = valueGamma;
  run.details["rbf"] = rbfSpec(used);
  const recon::MethodASystem& system = recon::sharedMethodASystem(params.frame, params.rbf);
  run.details["rbf_centres"] = system.centreEntries().size();
  run.details["rbf_shape_rad"] = system.interpolant().shapeRad();
  run.lines.push_back("RBF " + rbfSpec(used) + " over " +
                      std::to_string(system.centreEntries().size()) +
                      " centres, r0 = " + std::to_string(system.interpolant().shapeRad()) + " rad");
  return run;
}

MethodRun runMethodA(const SliceSet& slices, const MethodOptions& options) {
  return runMethodAWithGamma(slices, options, options.rbf.valueGamma);
}

MethodRun runMethodAGamma(const SliceSet& slices, const MethodOptions& options) {
  return runMethodAWithGamma(slices, options, kPaperValueGamma);
}

MethodRun runUniformWithGamma(const SliceSet& samples, const MethodOptions& options,
                              double valueGamma) {
  recon::ScatteredRbfParams params;
  params.frame = options.onionFrame;
  params.rbf = options.rbf;
  params.rbf.valueGamma = valueGamma;
  MethodRun run{recon::reconstructScattered(samples, params),
                exrMethodValue(valueGamma == 1.0 ? MethodId::Uniform : MethodId::UniformGamma,
                               options.isotropic),
                {},
                {},
                {}};
  MethodOptions used = options;
  used.rbf.valueGamma = valueGamma;
  run.details["value_gamma"] = valueGamma;
  run.details["rbf"] = rbfSpec(used);
  std::size_t onSlices = 0;
  for (const Slice& s : samples.slices()) {
    if (s.id.kind != SliceKind::Point) onSlices += s.samples.size();
  }
  run.details["rbf_centres"] = samples.sampleCount();
  run.lines.push_back("RBF " + rbfSpec(used) + " over " + std::to_string(samples.sampleCount()) +
                      " samples at their own directions");
  if (onSlices > 0) {
    run.warnings.push_back(std::to_string(onSlices) +
                           " samples lie on slices; the uniform method interpolates them as "
                           "points (made for `slicecap sample --uniform`)");
  }
  return run;
}

MethodRun runUniform(const SliceSet& samples, const MethodOptions& options) {
  return runUniformWithGamma(samples, options, options.rbf.valueGamma);
}

MethodRun runUniformGamma(const SliceSet& samples, const MethodOptions& options) {
  return runUniformWithGamma(samples, options, kPaperValueGamma);
}

MethodRun runHalfway(const SliceSet& slices, const MethodOptions& options) {
  recon::HalfwayParams params;
  params.isotropic = options.isotropic;
  params.torusRule = options.torusRule;
  recon::HalfwayReport report;
  MethodRun run{recon::reconstructHalfway(slices, params, &report),
                exrMethodValue(MethodId::Halfway, options.isotropic),
                {},
                {},
                {}};
  run.details["treated_isotropic"] = report.treatedIsotropic;
  run.details["axial_variation"] =
      report.axialVariation ? nlohmann::json(*report.axialVariation) : nlohmann::json();
  run.details["neighbours"] = params.neighbours;
  const std::string variation =
      report.axialVariation ? std::to_string(*report.axialVariation) : std::string("none");
  run.lines.push_back(report.treatedIsotropic
                          ? "isotropic (axial variation " + variation +
                                "): Method B from 30 to 75 deg, halfway neighbours below 30 deg"
                          : "anisotropic (axial variation " + variation +
                                "): every unmeasured entry from its halfway neighbours");
  if (report.treatedIsotropic && !report.methodB.allConverged())
    run.warnings.push_back("some lobe fits did not converge; their closed form was used");
  return run;
}

MethodRun runPriorAs(MethodId id, const SliceSet& slices, const MethodOptions& options,
                     bool fitEveryCell = false) {
  prior::PriorParams params;
  params.isotropicOnly = options.isotropic;
  params.fitEveryCell = fitEveryCell;
  params.frameAsOneSample = !options.priorCellFrameEffect;
  prior::PriorReport report;
  MethodRun run{prior::reconstructWithPrior(slices, prior::defaultPriorModel(), params, &report),
                exrMethodValue(id, options.isotropic),
                {},
                {},
                {}};
  nlohmann::json pairs = nlohmann::json::array();
  for (ElevationPair p : report.measuredPairs)
    pairs.push_back(std::to_string(p.thetaIDeg) + "/" + std::to_string(p.thetaVDeg));
  run.details["prior"] = {
      {"file", prior::locatePriorModel().string()},     {"measured_pairs", pairs},
      {"anisotropy_terms", report.anisotropyTermsUsed}, {"isotropic_gcv", report.isotropicScore},
      {"anisotropic_gcv", report.anisotropicScore},     {"fit_rms_log", report.fitRmsLog},
      {"dynamic_range_log", report.dynamicRangeLog},    {"prior_weight", report.priorWeight},
      {"method_b_blended", report.methodBBlended},
      {"points_fitted", report.samples},                {"frame_groups", report.frameGroups}};
  run.lines.push_back(
      "prior fit: RMS log residual " + std::to_string(report.fitRmsLog) +
      (report.anisotropyTermsUsed ? "; half-vector anisotropy terms used" : "; isotropic fit"));
  char blend[160];
  std::snprintf(blend, sizeof blend,
                report.methodBBlended
                    ? "samples' dynamic range %.2f (log): blended with Method B, prior weight %.2f"
                    : "samples' dynamic range %.2f (log): prior alone",
                report.dynamicRangeLog, report.priorWeight);
  run.lines.push_back(blend);
  if (report.measuredPairs.size() < kMeasuredPairs.size())
    run.warnings.push_back("only " + std::to_string(report.measuredPairs.size()) +
                           " elevation pairs measured; the others come from the prior alone");
  return run;
}

MethodRun runPrior(const SliceSet& slices, const MethodOptions& options) {
  return runPriorAs(MethodId::Prior, slices, options);
}

// The prior fitted to each bin's value from the window cells (docs/method.md §9.4).
MethodRun runPriorCells(const SliceSet& slices, const MethodOptions& options) {
  MethodRun run = runPriorAs(MethodId::PriorCells, slices.cellReading(), options,
                             options.priorFitsEveryCell);
  sayCellReading(slices, run);
  // Said only when every cell was fitted: slices without cell frames (a slice CSV, a session
  // read without cells) are the per-bin fit whatever the option, as before it was the default.
  if (options.priorFitsEveryCell && run.details["prior"]["frame_groups"].get<std::size_t>() > 0)
    run.lines.push_back("prior fitted to every window cell, one frame's cells as a group");
  return run;
}

// A method's row of the registry: its name comes from the table (method_id.cpp).
Method entry(MethodId id, std::string summary,
             std::function<MethodRun(const SliceSet&, const MethodOptions&)> run) {
  const Acquisition acquisition = methodInfo(id).reads == SliceSubset::PointSamples
                                      ? Acquisition::UniformGrid13
                                      : Acquisition::Slices;
  return {id, cliName(id), std::move(summary), std::move(run), acquisition};
}

}  // namespace

const std::vector<Method>& reconstructionMethods() {
  // In MethodId's order (findMethod(MethodId) indexes it).
  static const std::vector<Method> methods{
      entry(MethodId::B,
            "Method B of the paper (docs/method.md section 4): slice-sum subspaces, lobe-weighted "
            "elevation blends",
            runMethodB),
      entry(MethodId::A,
            "Method A of the paper (docs/method.md section 5): slice-sum subspaces, 4-D RBF in "
            "onion coordinates",
            runMethodA),
      entry(MethodId::Uniform,
            "the uniform baseline (docs/method.md section 6.3): RBF over point samples, e.g. "
            "sample --uniform 13",
            runUniform),
      entry(MethodId::AGamma,
            "Method A interpolating v^(1/2.2), close to the paper's 8-bit sRGB data "
            "(docs/method.md section 6.2)",
            runMethodAGamma),
      entry(MethodId::UniformGamma, "the uniform baseline interpolating v^(1/2.2), as a-gamma",
            runUniformGamma),
      entry(MethodId::Halfway,
            "slicecap's improvement (docs/method.md section 7): unmeasured entries from the "
            "nearest\nmeasured ones in halfway angle; for isotropic materials only where Method B "
            "extrapolates",
            runHalfway),
      entry(MethodId::Prior,
            "learned prior (issue 10): PCA of measured tables fitted at the samples' actual "
            "angles, half-vector anisotropy, measured slices kept; any subset of slices",
            runPrior),
      entry(MethodId::BCells,
            "Method B on slice values from the window cells nearest each bin centre in angle\n"
            "(docs/method.md section 9): a peak the window centre missed is read where a cell saw "
            "it",
            runMethodBCells),
      entry(MethodId::PriorCells,
            "the learned prior fitted to every window cell of the capture, one frame's cells as "
            "one sample\n(docs/method.md section 9); each bin's value from the cells with "
            "--prior-cells-per-bin or a slice CSV",
            runPriorCells),
  };
  return methods;
}

const Method& findMethod(MethodId id) {
  const Method& method = reconstructionMethods().at(static_cast<std::size_t>(methodInfo(id).id));
  return method;
}

const Method& findMethod(const std::string& name) { return findMethod(methodNamed(name)); }

MethodRun runForSession(MethodId id, const SliceSet& slices) {
  MethodOptions options;
  options.isotropic = sessionTakesIsotropicForm(id, slices);
  return findMethod(id).run(slices, options);
}

std::string methodHelpLines() {
  std::size_t width = 0;
  for (const Method& m : reconstructionMethods())
    width = std::max(width, m.name.size());
  std::string lines;
  for (const Method& m : reconstructionMethods()) {
    std::string summary = m.summary;
    // A summary's further lines start in the summaries' column.
    for (std::size_t at = summary.find('\n'); at != std::string::npos;
         at = summary.find('\n', at + 1))
      summary.insert(at + 1, std::string(width + 4, ' '));
    lines += "  " + m.name + std::string(width + 2 - m.name.size(), ' ') + summary + "\n";
  }
  return lines;
}

}  // namespace slicecap::methods
