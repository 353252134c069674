// Which tables `slicecap eval` and `preview` read: files, folders of tables, built-in materials.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::cli {

/// \brief One material to evaluate: its name (file stem or built-in name), where it comes from,
/// and how to get its table (reading may throw io::IoError naming the file).
struct MaterialSource {
  std::string name;
  std::string origin;
  std::function<Abrdf()> load;
};

/// \brief Each argument is a table file (.exr, .f32), a folder (its .exr and .f32 files, sorted
/// by name), a built-in material name, or builtin:anisotropic, builtin:isotropic, builtin:all.
/// Throws CommandError naming an argument that is none of these, and UsageError naming a
/// material that two arguments give (the same name twice), before anything runs.
std::vector<MaterialSource> resolveMaterials(const std::vector<std::string>& arguments);

}  // namespace slicecap::cli
