// `slicecap fit`: a parametric material (diffuse + anisotropic GGX, optionally sheen and a clear
// coat) fitted to a measured table, written as JSON (docs/material-fit.md), and optionally
// exported to glTF, MaterialX and Mitsuba 3 (docs/material-export.md); given a material JSON, only
// the exports.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>

#include "material_exports.hpp"
#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/fit/material_fit.hpp"
#include "slicecap/fit/material_json.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/material_export/material_reader.hpp"
#include "texture_fit_command.hpp"

namespace slicecap::cli {
namespace {

bool isMaterialJson(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".json";
}

// A fit made earlier: read back strictly (a file that is not a completed fit is refused, naming it)
// and exported as it is, without fitting again.
int exportExisting(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path input = args.positional[0];
  const MaterialExportPaths exports = materialExportPaths(args);
  if (args.value("output") || args.flag("no-sheen") || args.flag("no-coat") ||
      args.value("max-iterations") ||
      args.value("threads"))
    throw UsageError("fit: " + input.string() +
                     " is a fitted material: only --gltf, --mtlx and --mitsuba apply to it");
  if (!exports.any())
    throw UsageError("fit: " + input.string() +
                     " is a fitted material: say what to export (--gltf, --mtlx, --mitsuba)");
  refuseClashingPaths({{"the input", input}}, exports.named());
  const fit::FittedMaterial material = material_export::readFittedMaterial(input);
  const PreparedExports prepared = prepareMaterialExports(material, input.string(), exports);
  io::replaceFilesTogether(prepared.files);
  printExportReports(prepared, io);
  return 0;
}

int run(const ParsedArgs& args, Streams& io) {
  if (isMaterialJson(args.positional[0])) return exportExisting(args, io);
  if (std::filesystem::is_directory(args.positional[0])) return runTextureFit(args, io);
  if (args.value("threads"))
    throw UsageError("fit: --threads applies to a BTF directory (one table is fitted on one core)");
  const std::filesystem::path input = args.positional[0];
  const std::filesystem::path output = args.required("output");
  const MaterialExportPaths exports = materialExportPaths(args);
  std::vector<NamedPath> outputs = exports.named();
  outputs.insert(outputs.begin(), {"-o", output});
  refuseClashingPaths({{"the input", input}}, outputs);
  fit::FitOptions options;
  options.trySheen = !args.flag("no-sheen");
  options.tryCoat = !args.flag("no-coat");
  const double iterations = args.number("max-iterations", options.maxIterations);
  if (!(iterations >= 1.0 && iterations <= 10000.0) || iterations != std::floor(iterations))
    throw UsageError("fit: --max-iterations must be a whole number from 1 to 10000");
  options.maxIterations = static_cast<int>(iterations);

  const Abrdf table = io::readTable(input);
  const fit::FitResult result = fit::fitMaterial(table, input.string(), options);
  // The material and its exports replace their files together: a failed export (a full disk, a
  // folder that does not exist) must not have cost an earlier fit kept at the same -o.
  const fit::FittedMaterial& m = result.material;
  const PreparedExports prepared = prepareMaterialExports(m, input.string(), exports);
  std::vector<io::PendingFile> files{
      {output, fit::materialJsonText(fit::materialJson(result, input.string()))}};
  files.insert(files.end(), prepared.files.begin(), prepared.files.end());
  io::replaceFilesTogether(files);

  io.out << std::fixed << std::setprecision(3) << "fitted " << toString(m.model) << ": alpha_t "
         << m.alphaTangent << ", alpha_b " << m.alphaBitangent << ", tangent "
         << std::setprecision(1) << m.tangentDeg << " deg; dE " << std::setprecision(2)
         << result.metrics.deltaE << ", RMSE " << result.metrics.rmse << ", PSNR "
         << result.metrics.psnrDb << " dB\n"
         << "  " << result.choiceReason << "\n"
         << "wrote " << output.string() << "\n";
  printExportReports(prepared, io);
  return 0;
}

std::vector<OptionSpec> fitOptions() {
  std::vector<OptionSpec> options = {
      {"output", 'o', "MATERIAL.json", "where to write the fitted material (replaced whole)"},
      {"no-sheen", 0, "", "no sheen term"},
      {"no-coat", 0, "", "no clear coat"},
      {"max-iterations", 0, "N", "Levenberg-Marquardt iterations per solve (default 200)"},
      {"threads", 0, "N", "BTF_DIR: texels fitted at once (default: all cores)"}};
  for (OptionSpec& o : materialExportOptions()) options.push_back(std::move(o));
  return options;
}

}  // namespace

Command fitCommand() {
  return {{"fit",
           "TABLE.exr|TABLE.f32 -o MATERIAL.json [--no-sheen] [--no-coat] [--max-iterations N]\n"
           "                    [--gltf F.gltf|F.glb] [--mtlx F.mtlx] [--mitsuba F.xml]\n"
           "       slicecap fit MATERIAL.json [--gltf F.gltf|F.glb] [--mtlx F.mtlx] [--mitsuba F.xml]\n"
           "       slicecap fit BTF_DIR -o MAPS_DIR [--threads N] [--max-iterations N]",
           "Fit a parametric material to a measured table: diffuse RGB + anisotropic GGX (f0 RGB,\n"
           "alpha along and across the tangent, tangent angle), plus a Charlie sheen term and a clear\n"
           "coat (glTF's, IOR 1.5) each when it lowers the fit's mean dE clearly. The JSON holds the\n"
           "parameters with units, conventions and sigmas, every candidate's dE/RMSE/PSNR against\n"
           "the table and why the model was chosen (docs/material-fit.md). Fails, writing nothing,\n"
           "on a table that is not a BRDF or a fit that does not converge.\n"
           "--gltf/--mtlx/--mitsuba also write the material for glTF viewers and Blender, MaterialX\n"
           "(OpenPBR) and Mitsuba 3, and print what each format cannot express\n"
           "(docs/material-export.md). Given a MATERIAL.json written by an earlier fit, only the\n"
           "exports are written; a file that is not a completed fit is refused, naming it.\n"
           "BTF_DIR (written by `slicecap btf`): every texel fitted (diffuse + anisotropic GGX\n"
           "with a tilted shading normal, no sheen), warm-started from its neighbour, on\n"
           "--threads threads; MAPS_DIR gets glTF's texture maps as PNG (base colour,\n"
           "metallic-roughness, anisotropy, specular, the normal map of the lobes' tilts: flat,\n"
           "and named in maps.json, where no specular lobe locates one), mask.png (0: a texel not\n"
           "fitted, each named), material.gltf (the maps on a plane) and maps.json.",
           fitOptions(),
           1,
           1},
          run};
}

}  // namespace slicecap::cli
