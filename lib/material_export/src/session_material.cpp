// The fit of a session's exported table, as the export's material files.
#include "slicecap/material_export/session_material.hpp"

#include <cstdio>
#include <memory>

#include "slicecap/fit/material_json.hpp"
#include "slicecap/material_export/gltf_writer.hpp"
#include "slicecap/material_export/mitsuba_writer.hpp"
#include "slicecap/material_export/mtlx_writer.hpp"

namespace slicecap::material_export {

SessionMaterial sessionMaterial(const Abrdf& table, const std::string& source) {
  SessionMaterial result;
  result.fit = fit::fitMaterial(table, source);
  // Shared by the writers, which the caller may run after this returns.
  auto fitted = std::make_shared<const fit::FitResult>(result.fit);
  result.files = {
      {"-material.json",
       [fitted, source](const std::filesystem::path& path) {
         fit::writeMaterialJson(path, fit::materialJson(*fitted, source));
       }},
      {"-material.gltf",
       [fitted, source](const std::filesystem::path& path) { writeGltf(path, fitted->material, source); }},
      {"-material.mtlx",
       [fitted, source](const std::filesystem::path& path) { writeMtlx(path, fitted->material, source); }},
      {"-material-mitsuba.xml",
       [fitted, source](const std::filesystem::path& path) { writeMitsuba(path, fitted->material, source); }},
  };
  char line[200];
  std::snprintf(line, sizeof line, "%s fitted (dE %.2f against the table)",
                fit::toString(result.fit.material.model).data(), result.fit.metrics.deltaE);
  result.summary = line;
  return result;
}

}  // namespace slicecap::material_export
