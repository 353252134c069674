// `slicecap reconstruct`: slice CSV -> 81 x 81 ABRDF EXR.
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/methods/method_fallback.hpp"
#include "slicecap/methods/rbf_spec.hpp"

namespace slicecap::cli {
namespace {

using methods::MethodId;

recon::TorusRule parseTorusRule(const std::string& text) {
  if (text == "square") return recon::TorusRule::FundamentalSquare;
  if (text == "pi-symmetric") return recon::TorusRule::PiSymmetric;
  throw UsageError("--torus: '" + text + "' is not one of square, pi-symmetric");
}

int run(const ParsedArgs& args, Streams& io) {
  const methods::Method& method =
      methods::findMethod(args.value("method").value_or(methods::cliName(MethodId::B)));
  methods::MethodOptions options;
  options.isotropic = args.flag("isotropic");
  options.torusRule = parseTorusRule(args.value("torus").value_or("square"));
  if (const std::optional<std::string> spec = args.value("rbf"))
    methods::applyRbfSpec(*spec, options);
  const std::filesystem::path input = args.positional[0];
  const std::filesystem::path output = args.required("output");
  refuseClashingPaths({{"the input", input}}, {{"-o", output}});

  const SliceSet slices = io::readSliceCsv(input);
  const auto start = std::chrono::steady_clock::now();
  const methods::MethodRun result = methods::runMethodOrPrior(method, slices, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::writeAbrdfExr(output, result.table,
                    {{"method", result.exrMethodName},
                     {"source", input.filename().string()},
                     {"samples", std::to_string(slices.sampleCount())}});

  if (args.flag("json")) {
    nlohmann::json j = result.details;
    j.update({{"input", input.string()},
              {"output", output.string()},
              {"method", result.exrMethodName},
              {"samples", slices.sampleCount()},
              {"seconds", seconds}});
    for (const Slice& s : slices.slices())
      j["slices"].push_back({{"slice", toString(s.id)}, {"samples", s.samples.size()}});
    io.out << j.dump(2) << "\n";
  } else {
    io.out << "read " << slices.sampleCount() << " samples in " << slices.slices().size()
           << " slices from " << input.string() << "\n";
    for (const Slice& s : slices.slices())
      io.out << "  " << toString(s.id) << ": " << s.samples.size() << "\n";
    for (const std::string& line : result.lines)
      io.out << "  " << line << "\n";
    io.out << "Method " << result.exrMethodName << " in " << seconds * 1e3 << " ms; wrote "
           << output.string() << "\n";
  }
  for (const std::string& warning : result.warnings)
    io.err << "warning: " << warning << "\n";
  return 0;
}

}  // namespace

Command reconstructCommand() {
  std::string description =
      "Reconstruct the full 81 x 81 ABRDF from measured slices and write it as OpenEXR.\n"
      "SLICES.csv holds the samples (slice,theta_i,phi_i,theta_v,phi_v,r,g,b); each sample "
      "belongs\n"
      "to the slice of its kind at its elevations rounded to the nearest Bonn ring (30 or 75).\n"
      "Methods b, a and halfway need the axial and diagonal slices at 30/30, 30/75, 75/30, 75/75, "
      "or "
      "with\n"
      "--isotropic only the four diagonal ones; uniform takes point samples (sample --uniform).\n"
      "\nmethods:\n";
  description += methods::methodHelpLines();
  return {{"reconstruct",
           "SLICES.csv -o OUT.exr [--method NAME] [--isotropic] [--torus square|pi-symmetric] "
           "[--rbf SPEC] [--json]",
           description,
           {{"output", 'o', "OUT.exr", "where to write the ABRDF (required)"},
            {"method", 0, "NAME",
             "reconstruction method (default " + methods::cliName(MethodId::B) + ")"},
            {"isotropic", 0, "", "use the diagonal slices only (eq. 5)"},
            {"torus", 0, "RULE", "square (default) or pi-symmetric (docs/method.md section 3.2)"},
            {"rbf", 0, "SPEC",
             "a, uniform: the RBF's open choices, key=value,... (kernel=mq|imq|r|r3, "
             "poly=const|linear, r0=SCALE, frame=relative|absolute, gamma=G); see "
             "docs/reference/commands.md"},
            {"json", 0, "", "print a JSON summary instead of text"}},
           1,
           1},
          run};
}

}  // namespace slicecap::cli
