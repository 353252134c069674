// `slicecap fit`: a parametric material (diffuse + anisotropic GGX, optionally sheen) fitted to a
// measured table, written as JSON (docs/material-fit.md).
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/fit/material_fit.hpp"
#include "slicecap/fit/material_json.hpp"
#include "slicecap/io/table_file.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path input = args.positional[0];
  const std::filesystem::path output = args.required("output");
  refuseClashingPaths({{"the input", input}}, {{"-o", output}});
  fit::FitOptions options;
  options.trySheen = !args.flag("no-sheen");
  const double iterations = args.number("max-iterations", options.maxIterations);
  if (!(iterations >= 1.0 && iterations <= 10000.0) || iterations != std::floor(iterations))
    throw UsageError("fit: --max-iterations must be a whole number from 1 to 10000");
  options.maxIterations = static_cast<int>(iterations);

  const Abrdf table = io::readTable(input);
  const fit::FitResult result = fit::fitMaterial(table, input.string(), options);
  fit::writeMaterialJson(output, fit::materialJson(result, input.string()));

  const fit::FittedMaterial& m = result.material;
  io.out << std::fixed << std::setprecision(3) << "fitted " << toString(m.model) << ": alpha_t "
         << m.alphaTangent << ", alpha_b " << m.alphaBitangent << ", tangent "
         << std::setprecision(1) << m.tangentDeg << " deg; dE " << std::setprecision(2)
         << result.metrics.deltaE << ", RMSE " << result.metrics.rmse << ", PSNR "
         << result.metrics.psnrDb << " dB\n"
         << "  " << result.choiceReason << "\n"
         << "wrote " << output.string() << "\n";
  return 0;
}

}  // namespace

Command fitCommand() {
  return {{"fit",
           "TABLE.exr|TABLE.f32 -o MATERIAL.json [--no-sheen] [--max-iterations N]",
           "Fit a parametric material to a measured table: diffuse RGB + anisotropic GGX (f0 RGB,\n"
           "alpha along and across the tangent, tangent angle), plus a Charlie sheen term when it\n"
           "lowers the fit's mean dE clearly. The JSON holds the parameters with units, conventions\n"
           "and sigmas, every candidate's dE/RMSE/PSNR against the table and why the model was\n"
           "chosen (docs/material-fit.md). Fails, writing nothing, on a table that is not a BRDF or\n"
           "a fit that does not converge.",
           {{"output", 'o', "MATERIAL.json", "where to write the fitted material (replaced whole)"},
            {"no-sheen", 0, "", "fit diffuse + GGX only"},
            {"max-iterations", 0, "N", "Levenberg-Marquardt iterations per solve (default 200)"}},
           1,
           1},
          run};
}

}  // namespace slicecap::cli
