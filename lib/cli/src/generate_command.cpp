// `slicecap generate`: a built-in analytic material tabulated on the Bonn grid.
#include <filesystem>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/sim/material.hpp"

namespace slicecap::cli {
namespace {

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
  std::shared_ptr<const models::ReflectanceModel> model = models::findMaterial(name);
  // A model specification (ward:..., ggx:..., lambert:...), as simulate takes it: the truth of
  // a simulated capture of a material that is not built in.
  if (!model && name.find(':') != std::string::npos && !name.starts_with("woven")) {
    try {
      model = sim::loadMaterial(name);
    } catch (const sim::MaterialError& e) {
      throw UsageError(std::string("generate: ") + e.what());
    }
  }
  if (!model)
    throw UsageError("generate: unknown material '" + name + "' (see slicecap generate --list)");
  const std::filesystem::path output = args.required("output");
  const Abrdf table = models::tabulate(*model);
  if (output.extension() == ".f32") {
    io::writeF32Table(output, table);
  } else if (output.extension() == ".exr") {
    io::writeAbrdfExr(output, table,
                      {{"method", "analytic"}, {"material", name}, {"model", model->describe()}});
  } else {
    throw UsageError("generate: output must end in .exr or .f32");
  }
  io.out << "wrote " << name << " (" << model->describe() << ") to " << output.string() << "\n";
  return 0;
}

}  // namespace

Command generateCommand() {
  return {{"generate",
           "MATERIAL -o OUT.exr|OUT.f32 | --list",
           "Tabulate a built-in analytic material (Ward, anisotropic GGX, Blinn-Phong, Lambert, "
           "sheen) on\n"
           "the Bonn 81 x 81 grid: ground truth for simulated captures. MATERIAL may also be a\n"
           "model specification as simulate takes it (ward:..., ggx:..., lambert:...).",
           {{"output", 'o', "OUT", "where to write the table (.exr or .f32)"},
            {"list", 0, "", "list the built-in materials and their parameters"}},
           0,
           1},
          run};
}

}  // namespace slicecap::cli
