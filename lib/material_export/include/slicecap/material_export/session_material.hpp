// A session export's fitted material: the fit of the exported table and the files it gives.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/fit/material_fit.hpp"

namespace slicecap::material_export {

/// \brief One file of the material, written by `write` to the path it is given (the caller picks
/// the folder and prefix; `suffix` ends the name, e.g. "-material.json").
struct MaterialFile {
  std::string suffix;
  std::function<void(const std::filesystem::path&)> write;
};

/// \brief The fit and its files: the material JSON (lib/fit's format, what `slicecap fit`
/// writes), a glTF 2.0 asset, a MaterialX document and a Mitsuba 3 snippet.
struct SessionMaterial {
  fit::FitResult fit;
  std::vector<MaterialFile> files;
  std::string summary;  ///< one line: the model chosen and its dE against the table
};

/// \brief Fits `table` (fit::fitMaterial with its default options; `source` names it in every
/// message and in the files) and prepares its files; nothing is written until a file's `write`
/// is called, and each write throws io::IoError naming its path. Throws fit::FitError naming
/// `source` when the table cannot be fitted.
SessionMaterial sessionMaterial(const Abrdf& table, const std::string& source);

}  // namespace slicecap::material_export
