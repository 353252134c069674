// The --gltf/--mtlx/--mitsuba options of `slicecap fit`: writing a fitted material to the formats
// other tools read, and printing what each cannot express (docs/material-export.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "path_clash.hpp"
#include "slicecap/cli/args.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/fit/fitted_material.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/material_export/conversion_loss.hpp"

namespace slicecap::cli {

/// \brief Where to write each export; absent = not asked for.
struct MaterialExportPaths {
  std::optional<std::filesystem::path> gltf, mtlx, mitsuba;

  bool any() const { return gltf || mtlx || mitsuba; }
  /// \brief The asked-for outputs with their option names, for refuseClashingPaths.
  std::vector<NamedPath> named() const;
};

/// \brief The three options' specs, for a command's CommandSpec.
std::vector<OptionSpec> materialExportOptions();

/// \brief The paths the command line asks for. Never throws.
MaterialExportPaths materialExportPaths(const ParsedArgs& args);

/// \brief Every asked-for export of `material` (whose origin `source` goes into the files), made
/// in memory, not yet written: the files for io::replaceFilesTogether, with the other outputs of
/// the command, so that a failed write leaves every one of them as it was. Never throws.
struct PreparedExports {
  std::vector<io::PendingFile> files;
  std::vector<material_export::ExportReport> reports;  ///< one per file, in the same order
};
PreparedExports prepareMaterialExports(const fit::FittedMaterial& material,
                                       const std::string& source, const MaterialExportPaths& paths);

/// \brief Prints, per written export, "wrote PATH (FORMAT)" and each conversion loss on `io.out`.
void printExportReports(const PreparedExports& exports, Streams& io);

}  // namespace slicecap::cli
