// A session's tables: the registry's reconstruction, a preview sheet, the isotropy test on the
// prior, and the exported table's fitted material.
#include "method_tables.hpp"

#include <cstdio>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/material_export/session_material.hpp"
#include "slicecap/methods/methods.hpp"
#include "slicecap/prior/isotropy_test.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/render/sheets.hpp"

namespace slicecap::rig {

// The registry decides the form (isotropic for a session without axial sweeps), so the table
// and the `slicecap:method` the daemon writes beside it agree (methods::runForSession).
Abrdf MethodTables::reconstruct(const SliceSet& slices, const std::string& method) {
  return methods::runForSession(methods::methodNamed(method), slices).table;
}

void MethodTables::preview(const Abrdf& table, const std::filesystem::path& png) {
  char line[96];
  std::snprintf(line, sizeof line, "normalised to max f cos = %.4g 1/sr",
                eval::cosWeightedMaximum(table));
  io::writePng(png, render::previewSheet(png.stem().string(), {line}, table).toPng());
}

daemon::IsotropyAssessment MethodTables::isotropy(const SliceSet& slices) {
  const prior::IsotropyVerdict verdict = prior::testIsotropy(slices, prior::defaultPriorModel());
  return {verdict.isotropic, verdict.informative, verdict.reason};
}

// The exported table's fitted material (docs/material-fit.md, docs/material-export.md).
daemon::ExportedMaterial MethodTables::material(const Abrdf& table, const std::string& tableName) {
  material_export::SessionMaterial fitted = material_export::sessionMaterial(table, tableName);
  daemon::ExportedMaterial exported;
  exported.summary = fitted.summary;
  for (material_export::MaterialFile& file : fitted.files)
    exported.files.push_back({std::move(file.suffix), std::move(file.write)});
  return exported;
}

}  // namespace slicecap::rig
