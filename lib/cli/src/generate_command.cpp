// `slicecap generate`: a built-in analytic material, or a fitted MATERIAL.json, tabulated on the
// Bonn grid.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/material_export/material_reader.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/sim/material.hpp"

namespace slicecap::cli {
namespace {

bool endsInJson(const std::string& name) {
  std::string extension = std::filesystem::path(name).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".json";
}

void writeTable(const std::filesystem::path& output, const Abrdf& table,
                const io::ExrAttributes& attributes) {
  if (output.extension() == ".f32") {
    io::writeF32Table(output, table);
  } else if (output.extension() == ".exr") {
    io::writeAbrdfExr(output, table, attributes);
  } else {
    throw UsageError("generate: output must end in .exr or .f32");
  }
}

// A material `slicecap fit` wrote, tabulated by fit::tabulate: the code the fit's own dE is
// computed with, so the table is the material the fit judged. The reader refuses (naming the
// file) anything that is not a completed fit, rather than tabulate a default.
int tabulateFittedMaterial(const std::filesystem::path& input, const std::filesystem::path& output,
                           Streams& io) {
  const fit::FittedMaterial material = material_export::readFittedMaterial(input);
  writeTable(output, fit::tabulate(material),
             {{"method", "fitted"},
              {"material", input.filename().string()},
              {"model", std::string(fit::toString(material.model))}});
  io.out << "wrote the fitted material " << input.string() << " (" << fit::toString(material.model)
         << ") to " << output.string() << "\n";
  return 0;
}

int run(const ParsedArgs& args, Streams& io) {
  if (args.flag("list")) {
    for (auto* list : {models::anisotropicMaterials, models::isotropicMaterials}) {
      for (const models::NamedMaterial& m : list())
        io.out << m.name << "  " << m.model->describe() << "\n";
    }
    return 0;
  }
  if (args.positional.size() != 1)
    throw UsageError("generate: expected a MATERIAL name (see --list)");
  const std::string name = args.positional[0];
  if (endsInJson(name)) return tabulateFittedMaterial(name, args.required("output"), io);
  std::shared_ptr<const models::ReflectanceModel> model = models::findMaterial(name);
  // A model specification (ward:..., ggx:..., lambert:..., woven[:...]), as simulate takes it:
  // the truth of a simulated capture of a material that is not built in (a patterned one's is
  // the window's area mean, sim::PatternedMaterial's evaluate).
  if (!model && (name.find(':') != std::string::npos || name == "woven")) {
    try {
      model = sim::loadMaterial(name);
    } catch (const sim::MaterialError& e) {
      throw UsageError(std::string("generate: ") + e.what());
    }
  }
  if (!model)
    throw UsageError("generate: unknown material '" + name + "' (see slicecap generate --list)");
  const std::filesystem::path output = args.required("output");
  writeTable(output, models::tabulate(*model),
             {{"method", "analytic"}, {"material", name}, {"model", model->describe()}});
  io.out << "wrote " << name << " (" << model->describe() << ") to " << output.string() << "\n";
  return 0;
}

}  // namespace

Command generateCommand() {
  return {{"generate",
           "MATERIAL|MATERIAL.json -o OUT.exr|OUT.f32 | --list",
           "Tabulate a built-in analytic material (Ward, anisotropic GGX, Blinn-Phong, Lambert, "
           "sheen) on\n"
           "the Bonn 81 x 81 grid: ground truth for simulated captures. MATERIAL may also be a\n"
           "model specification as simulate takes it (ward:..., ggx:..., lambert:...;\n"
           "woven[:...]: its window's area mean, what a capture's window mean reads).\n"
           "MATERIAL.json (written by `slicecap fit`): the fitted material's table, as the fit\n"
           "computed its own dE; a file that is not a completed fit is refused, naming it.",
           {{"output", 'o', "OUT", "where to write the table (.exr or .f32)"},
            {"list", 0, "", "list the built-in materials and their parameters"}},
           0,
           1},
          run};
}

}  // namespace slicecap::cli
