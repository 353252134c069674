// The fitted material as JSON (docs/material-fit.md describes every field).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "slicecap/fit/material_fit.hpp"

namespace slicecap::fit {

/// \brief Format name and version written in every file ("format", "format_version").
/// Version 2 added "sheen_form" (the sheen in KHR_materials_sheen's layering); a version-1 file has
/// none and holds the additive sheen (SheenForm::Additive).
inline constexpr const char* kMaterialFormat = "slicecap-material";
inline constexpr int kMaterialFormatVersion = 2;
/// \brief The version before "sheen_form", still read (its sheen is SheenForm::Additive).
inline constexpr int kMaterialFormatVersionAdditiveSheen = 1;

/// \brief The document of a fit of the table at `source`. Never throws.
nlohmann::ordered_json materialJson(const FitResult& result, const std::string& source);

/// \brief The file's text of `document` (what writeMaterialJson writes). Never throws.
std::string materialJsonText(const nlohmann::ordered_json& document);

/// \brief Writes `document` to `path` through a temporary renamed into place, so a failed write
/// never leaves a partial file nor costs an old one. Throws io::IoError naming the path.
void writeMaterialJson(const std::filesystem::path& path, const nlohmann::ordered_json& document);

}  // namespace slicecap::fit
