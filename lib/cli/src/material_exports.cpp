// Dispatch to lib/material_export and the report of conversion losses.
#include "material_exports.hpp"

#include <iomanip>
#include <ostream>

#include "slicecap/material_export/gltf_writer.hpp"
#include "slicecap/material_export/mitsuba_writer.hpp"
#include "slicecap/material_export/mtlx_writer.hpp"

namespace slicecap::cli {
namespace {

void printReport(const std::filesystem::path& path, const material_export::ExportReport& report,
                 std::ostream& out) {
  out << "wrote " << path.string() << " (" << report.format << ")";
  if (report.losses.empty()) {
    out << ": the fitted material exactly\n";
  } else {
    out << "; what it cannot express:\n";
    for (const material_export::ConversionLoss& loss : report.losses)
      out << "  - " << toString(loss.kind) << ": " << loss.detail << "\n";
  }
  if (report.measured)
    out << std::fixed << std::setprecision(2) << "  its BRDF against the fit: dE "
        << report.measured->deltaE << ", RMSE " << report.measured->rmse << ", PSNR "
        << report.measured->psnrDb << " dB (slicecap compare's metrics)\n"
        << std::defaultfloat;
}

}  // namespace

std::vector<NamedPath> MaterialExportPaths::named() const {
  std::vector<NamedPath> out;
  if (gltf) out.push_back({"--gltf", *gltf});
  if (mtlx) out.push_back({"--mtlx", *mtlx});
  if (mitsuba) out.push_back({"--mitsuba", *mitsuba});
  return out;
}

std::vector<OptionSpec> materialExportOptions() {
  return {{"gltf", 0, "F.gltf|F.glb",
           "also write the material as glTF 2.0 on a sphere and a cylinder (.glb: binary)"},
          {"mtlx", 0, "F.mtlx", "also write a MaterialX document (OpenPBR + standard_surface)"},
          {"mitsuba", 0, "F.xml", "also write a Mitsuba 3 scene snippet (BSDF id slicecap_fit)"}};
}

MaterialExportPaths materialExportPaths(const ParsedArgs& args) {
  MaterialExportPaths paths;
  if (const auto v = args.value("gltf")) paths.gltf = *v;
  if (const auto v = args.value("mtlx")) paths.mtlx = *v;
  if (const auto v = args.value("mitsuba")) paths.mitsuba = *v;
  return paths;
}

PreparedExports prepareMaterialExports(const fit::FittedMaterial& material,
                                       const std::string& source, const MaterialExportPaths& paths) {
  PreparedExports out;
  const auto add = [&](const std::filesystem::path& path, std::string contents,
                       material_export::ExportReport report) {
    out.files.push_back({path, std::move(contents)});
    out.reports.push_back(std::move(report));
  };
  if (paths.gltf) {
    material_export::GltfAsset asset = material_export::gltfAsset(material, source);
    add(*paths.gltf, material_export::gltfFileContents(asset, *paths.gltf), std::move(asset.report));
  }
  if (paths.mtlx) {
    material_export::MtlxExport e = material_export::mtlxDocument(material, source);
    add(*paths.mtlx, std::move(e.text), std::move(e.report));
  }
  if (paths.mitsuba) {
    material_export::MitsubaExport e = material_export::mitsubaSnippet(material, source);
    add(*paths.mitsuba, std::move(e.text), std::move(e.report));
  }
  return out;
}

void printExportReports(const PreparedExports& exports, Streams& io) {
  for (std::size_t i = 0; i < exports.files.size(); ++i)
    printReport(exports.files[i].target, exports.reports[i], io.out);
}

}  // namespace slicecap::cli
