// `slicecap preview`: a table's 81 x 81 layout and lit spheres in one PNG.
#include <cstdio>
#include <filesystem>
#include <ostream>

#include "eval_materials.hpp"
#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/cli/command_error.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/render/sheets.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path output = args.required("output");
  if (output.extension() != ".png") throw UsageError("preview: output must end in .png");
  const std::vector<MaterialSource> sources = resolveMaterials(args.positional);
  if (sources.size() != 1)
    throw UsageError("preview: " + args.positional[0] + " names " + std::to_string(sources.size()) +
                     " tables; give one");
  const MaterialSource& source = sources.front();
  refuseClashingPaths({{"the input", args.positional[0]}}, {{"-o", output}});
  const Abrdf table = source.load();
  std::vector<std::string> lines{source.origin};
  if (std::filesystem::path(source.origin).extension() == ".exr") {
    io::ExrAttributes attributes;
    io::readAbrdfExr(source.origin, &attributes);
    std::string text;
    for (const auto& [key, value] : attributes) {
      if (key != "layout" && key != "quantity") text += key + "=" + value + "  ";
    }
    if (!text.empty()) lines.push_back(text);
  }
  char line[128];
  const double maximum = eval::cosWeightedMaximum(table);
  std::snprintf(line, sizeof line,
                "normalised to max f cos = %.4g 1/sr; spheres: f cos(theta_i), same scale",
                maximum);
  lines.push_back(line);
  if (!(maximum > 0.0))
    throw CommandError(source.origin + ": the table has no positive value to show");
  io::writePng(output, render::previewSheet(source.name, lines, table).toPng());
  io.out << "wrote " << output.string() << "\n";
  return 0;
}

}  // namespace

Command previewCommand() {
  return {{"preview",
           "TABLE -o OUT.png",
           "Picture a table (EXR, .f32 or a built-in material name) so a person can judge it at a\n"
           "glance: the paper's 81 x 81 layout (light rows, view columns, blocks of subspaces; "
           "times\n"
           "cos(theta_i), normalised to the table's maximum, sRGB) and a sphere of the material "
           "lit by\n"
           "a distant point light from four directions (theta/phi from the viewing axis), on the "
           "same scale.",
           {{"output", 'o', "OUT.png", "where to write the picture (required)"}},
           1,
           1},
          run};
}

}  // namespace slicecap::cli
