// `slicecap reconstruct`: slice CSV -> 81 x 81 ABRDF EXR.
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/recon/method_b.hpp"

namespace slicecap::cli {
namespace {

recon::TorusRule parseTorusRule(const std::string& text) {
  if (text == "square") return recon::TorusRule::FundamentalSquare;
  if (text == "pi-symmetric") return recon::TorusRule::PiSymmetric;
  throw UsageError("--torus: '" + text + "' is not one of square, pi-symmetric");
}

int run(const ParsedArgs& args, Streams& io) {
  const std::string method = args.value("method").value_or("b");
  if (method != "b") throw UsageError("--method: '" + method + "' is not a known method (b)");
  recon::MethodBParams params;
  params.isotropic = args.flag("isotropic");
  params.torusRule = parseTorusRule(args.value("torus").value_or("square"));
  const std::filesystem::path input = args.positional[0];
  const std::filesystem::path output = args.required("output");

  const SliceSet slices = io::readSliceCsv(input);
  recon::MethodBReport report;
  const auto start = std::chrono::steady_clock::now();
  const Abrdf table = recon::reconstructMethodB(slices, params, &report);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string methodName = params.isotropic ? "B-isotropic" : "B";
  io::writeAbrdfExr(output, table,
                    {{"method", methodName},
                     {"source", input.filename().string()},
                     {"samples", std::to_string(slices.sampleCount())}});

  if (args.flag("json")) {
    nlohmann::json j{{"input", input.string()}, {"output", output.string()},
                     {"method", methodName},    {"samples", slices.sampleCount()},
                     {"seconds", seconds},      {"all_fits_converged", report.allConverged()}};
    for (const Slice& s : slices.slices())
      j["slices"].push_back({{"slice", toString(s.id)}, {"samples", s.samples.size()}});
    for (const recon::LineFit& f : report.fits) {
      j["fits"].push_back({{"line", f.line},
                           {"k", f.fit.lobe.k},
                           {"n", f.fit.lobe.n},
                           {"converged", f.fit.converged},
                           {"closed_form_fallback", f.usedClosedForm},
                           {"iterations", f.fit.iterations}});
    }
    io.out << j.dump(2) << "\n";
  } else {
    io.out << "read " << slices.sampleCount() << " samples in " << slices.slices().size()
           << " slices from " << input.string() << "\n";
    for (const Slice& s : slices.slices())
      io.out << "  " << toString(s.id) << ": " << s.samples.size() << "\n";
    for (const recon::LineFit& f : report.fits) {
      io.out << "  lobe fit, " << f.line << ": n = " << f.fit.lobe.n
             << (f.fit.converged ? "" : "  (Ceres did not converge; closed form used)") << "\n";
    }
    io.out << "Method " << methodName << " in " << seconds * 1e3 << " ms; wrote " << output.string()
           << "\n";
  }
  if (!report.allConverged()) {
    io.err << "warning: some lobe fits did not converge; their closed-form solution was used\n";
  }
  return 0;
}

}  // namespace

Command reconstructCommand() {
  return {
      {"reconstruct",
       "SLICES.csv -o OUT.exr [--method b] [--isotropic] [--torus square|pi-symmetric] [--json]",
       "Reconstruct the full 81 x 81 ABRDF from measured slices and write it as OpenEXR.\n"
       "SLICES.csv holds the samples (slice,theta_i,phi_i,theta_v,phi_v,r,g,b); each sample "
       "belongs to\n"
       "the slice of its kind at its elevations rounded to the nearest Bonn ring (30 or 75).\n"
       "Method b (METHOD.md 4) needs the axial and diagonal slices at 30/30, 30/75, 75/30, 75/75, "
       "or\n"
       "with --isotropic only the four diagonal ones.",
       {{"output", 'o', "OUT.exr", "where to write the ABRDF (required)"},
        {"method", 0, "NAME", "reconstruction method: b (default)"},
        {"isotropic", 0, "", "use the diagonal slices only (eq. 5)"},
        {"torus", 0, "RULE", "square (default) or pi-symmetric (METHOD.md 3.2)"},
        {"json", 0, "", "print a JSON summary instead of text"}},
       1,
       1},
      run};
}

}  // namespace slicecap::cli
