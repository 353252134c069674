// Resolution of eval's material arguments.
#include "eval_materials.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "slicecap/cli/args.hpp"
#include "slicecap/cli/command_error.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::cli {
namespace {

bool isTableFile(const std::filesystem::path& path) {
  return path.extension() == ".f32" || path.extension() == ".exr";
}

MaterialSource fromFile(const std::filesystem::path& path) {
  return {path.stem().string(), path.string(), [path] { return io::readTable(path); }};
}

MaterialSource fromModel(const models::NamedMaterial& m) {
  return {m.name, "built-in " + m.model->describe(),
          [model = m.model] { return models::tabulate(*model); }};
}

}  // namespace

std::vector<MaterialSource> resolveMaterials(const std::vector<std::string>& arguments) {
  std::vector<MaterialSource> sources;
  for (const std::string& argument : arguments) {
    const std::filesystem::path path(argument);
    if (argument == "builtin:anisotropic" || argument == "builtin:all") {
      for (const models::NamedMaterial& m : models::anisotropicMaterials())
        sources.push_back(fromModel(m));
    }
    if (argument == "builtin:isotropic" || argument == "builtin:all") {
      for (const models::NamedMaterial& m : models::isotropicMaterials())
        sources.push_back(fromModel(m));
    }
    if (argument.rfind("builtin:", 0) == 0) {
      if (argument != "builtin:anisotropic" && argument != "builtin:isotropic" &&
          argument != "builtin:all") {
        throw CommandError(argument +
                           ": not a material group (builtin:anisotropic, builtin:isotropic, "
                           "builtin:all)");
      }
    } else if (std::filesystem::is_directory(path)) {
      std::vector<std::filesystem::path> files;
      for (const auto& entry : std::filesystem::directory_iterator(path)) {
        if (entry.is_regular_file() && isTableFile(entry.path())) files.push_back(entry.path());
      }
      if (files.empty())
        throw CommandError(argument + ": folder holds no .exr or .f32 table");
      std::sort(files.begin(), files.end());
      for (const auto& file : files)
        sources.push_back(fromFile(file));
    } else if (std::filesystem::exists(path)) {
      sources.push_back(fromFile(path));
    } else if (const auto model = models::findMaterial(argument)) {
      sources.push_back(fromModel({argument, model}));
    } else {
      throw CommandError(argument +
                         ": no such file, folder or built-in material (see slicecap "
                         "generate --list)");
    }
  }
  // Rows, means and sheets (NAME.png) are by name: one material twice would count twice in the
  // means, and two tables of one name would share a sheet.
  std::map<std::string, const MaterialSource*> byName;
  for (const MaterialSource& source : sources) {
    const auto [first, added] = byName.emplace(source.name, &source);
    if (!added)
      throw UsageError("material '" + source.name + "' is given twice (" + first->second->origin +
                       (first->second->origin == source.origin ? "" : ", " + source.origin) +
                       "); give each material once");
  }
  return sources;
}

}  // namespace slicecap::cli
