// The texture mode of `slicecap fit`: a `slicecap btf` directory fitted texel by texel, written as
// glTF texture maps, a textured glTF and maps.json (docs/material-fit.md "Texture mode").
#include "texture_fit_command.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <thread>

#include "slicecap/btf/btf_files.hpp"
#include "slicecap/btf/texture_store.hpp"
#include "slicecap/fit/material_fit.hpp"
#include "slicecap/fit/material_json.hpp"
#include "slicecap/fit/texture_fit.hpp"
#include "slicecap/io/file_set.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/material_export/textured_gltf.hpp"

namespace slicecap::cli {
namespace {

using json = nlohmann::ordered_json;

// Failed texels named one a line on stderr up to this many; all of them are in maps.json.
constexpr std::size_t kNamedOnConsole = 20;

std::filesystem::path resolved(const std::filesystem::path& path) {
  return std::filesystem::weakly_canonical(std::filesystem::absolute(path));
}

// `under` is `root` or inside it.
bool within(const std::filesystem::path& under, const std::filesystem::path& root) {
  const auto [rootEnd, underAt] = std::mismatch(root.begin(), root.end(), under.begin(), under.end());
  return rootEnd == root.end();
}

// The maps must not land among the BTF's images (a later `slicecap btf -o` would delete them with
// its own files, and `-o` naming the BTF would replace what it reads), nor replace it.
void refuseOverlap(const std::filesystem::path& input, const std::filesystem::path& output) {
  const std::filesystem::path in = resolved(input), out = resolved(output);
  if (within(out, in))
    throw UsageError("fit: -o " + output.string() + " is the BTF directory " + input.string() +
                     " or inside it: write the maps to a directory of their own");
  if (within(in, out))
    throw UsageError("fit: -o " + output.string() + " contains the BTF directory " +
                     input.string() + ": it would be written over");
}

// The file set of the maps in MAPS_DIR (io::replaceFileSet): its manifest lists them, and a
// failed or interrupted write leaves the previous set whole.
constexpr const char* kMapsFileSet = "svbrdf";

// A row of texel tables straight from the half-float images: each image's row is contiguous.
void readRow(const btf::BtfTexture& texture, int row, std::vector<Abrdf>& tables) {
  const int n = texture.resolution();
  tables.assign(std::size_t(n), Abrdf());
  const std::size_t first = std::size_t(row) * std::size_t(n);
  for (int l = 0; l < Abrdf::kDirections; ++l)
    for (int v = 0; v < Abrdf::kDirections; ++v)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 3; ++c)
          tables[std::size_t(x)].channel(l, v, c) = texture.value(l, v, first + std::size_t(x), c);
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
  return values[values.size() / 2];
}

// What normal.png holds: fitted tilts, and how many fitted texels are flat and why.
std::string normalMapSummary(const fit::TextureFitResult& result) {
  const std::size_t flat = result.fitted - result.tiltFitted;
  return "fitted: the lobe's tilt of " + std::to_string(result.tiltFitted) + " texels; flat at " +
         std::to_string(flat) +
         " fitted texels whose lobe cannot locate a tilt (flat_normal_texels)" +
         " and at the texels not fitted";
}

json mapsJson(const fit::TextureFitResult& result, const material_export::GltfTextureMaps& maps,
              const std::string& source) {
  json failed = json::array();
  json flat = json::array();
  std::vector<double> rmse;
  for (std::size_t i = 0; i < result.texels.size(); ++i) {
    const fit::TexelFit& t = result.texels[i];
    if (t.status == fit::TexelStatus::Fitted) {
      rmse.push_back(t.rmseLevels);
      if (t.tilt != fit::TiltStatus::Fitted)
        flat.push_back({{"x", int(i % std::size_t(result.resolution))},
                        {"y", int(i / std::size_t(result.resolution))},
                        {"normal", std::string(toString(t.tilt))}});
      continue;
    }
    failed.push_back({{"x", int(i % std::size_t(result.resolution))},
                      {"y", int(i / std::size_t(result.resolution))},
                      {"status", std::string(toString(t.status))},
                      {"problem", t.problem}});
  }
  json losses = json::object();
  for (const auto& [kind, texels] : maps.lossCounts) losses[std::string(toString(kind))] = texels;
  return {{"format", "slicecap-svbrdf"},
          {"format_version", 1},
          {"source", source},
          {"model", "ggx"},
          {"resolution", result.resolution},
          {"texels_fitted", result.fitted},
          {"texels_multi_start", result.multiStart},
          {"rmse_levels_median", median(rmse)},
          {"rmse_levels_max", rmse.empty() ? 0.0 : *std::max_element(rmse.begin(), rmse.end())},
          {"seconds", result.seconds},
          {"threads", result.threads},
          {"ior", maps.ior},
          {"normal_map", normalMapSummary(result)},
          {"texels_tilt_fitted", result.tiltFitted},
          {"conversion_losses_texels", losses},
          {"failed_texels", failed},
          {"flat_normal_texels", flat}};
}

}  // namespace

int runTextureFit(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path input = args.positional[0];
  if (std::filesystem::exists(input / btf::kTextureStoreManifest))
    throw io::IoError(input.string() +
                      ": a captured texture (texture store), not a BTF: `slicecap btf " +
                      input.string() + " -o BTF` reconstructs its texels; then slicecap fit BTF");
  if (!std::filesystem::exists(input / btf::kBtfManifest))
    throw io::IoError(input.string() + ": a directory without " + btf::kBtfManifest +
                      ": not a BTF written by `slicecap btf`");
  if (args.value("gltf") || args.value("mtlx") || args.value("mitsuba"))
    throw UsageError("fit: " + input.string() + " is a BTF: its glTF is -o DIR/" +
                     material_export::kTexturedGltf + "; --gltf, --mtlx and --mitsuba apply to a table");
  if (args.flag("no-sheen") || args.flag("no-coat"))
    throw UsageError("fit: " + input.string() +
                     " is a BTF: its texels are fitted without sheen or coat already; --no-sheen "
                     "and --no-coat apply to a table");
  const std::filesystem::path output = args.required("output");
  refuseOverlap(input, output);
  if (std::filesystem::exists(output) && !std::filesystem::is_directory(output))
    throw io::IoError(output.string() + ": not a directory: the maps of " + input.string() +
                      " go into a directory (-o MAPS_DIR)");
  fit::TextureFitOptions options;
  const double threads = args.number("threads", 0.0);
  if (!(threads >= 0.0 && threads <= 256.0) || threads != std::floor(threads))
    throw UsageError("fit: --threads must be a whole number from 0 to 256");
  options.threads = threads > 0 ? int(threads) : int(std::max(1u, std::thread::hardware_concurrency()));
  const double iterations = args.number("max-iterations", options.maxIterations);
  if (!(iterations >= 1.0 && iterations <= 10000.0) || iterations != std::floor(iterations))
    throw UsageError("fit: --max-iterations must be a whole number from 1 to 10000");
  options.maxIterations = int(iterations);

  // btf.json first, whole: a bad window is named before the minutes of the fit, not after.
  const btf::BtfManifest manifest = btf::readBtfManifest(input);
  const btf::BtfTexture texture = btf::readBtfDirectory(input);
  const fit::TextureFitResult result = fit::fitTexture(
      texture.resolution(),
      [&](int row, std::vector<Abrdf>& tables) { readRow(texture, row, tables); }, options);
  std::size_t named = 0;
  for (const fit::TexelFit& t : result.texels)
    if (t.status != fit::TexelStatus::Fitted && named++ < kNamedOnConsole)
      io.err << "warning: " << input.string() << ": " << t.problem << "\n";
  const std::size_t failed = result.texels.size() - result.fitted;
  if (failed > kNamedOnConsole)
    io.err << "warning: ... and " << failed - kNamedOnConsole << " more texels not fitted (all in "
           << (output / "maps.json").string() << ")\n";
  if (result.fitted == 0)
    throw fit::FitError(input.string() + ": no texel could be fitted (" + result.texels.front().problem +
                        ", ...); nothing written");

  const material_export::GltfTextureMaps maps = material_export::gltfTextureMaps(result);
  const double widthM = manifest.windowMm.widthMm() / 1000.0;
  const double heightM = manifest.windowMm.heightMm() / 1000.0;
  // The maps, material.gltf and maps.json replace the previous ones as one set: a fit that fails
  // while writing (a full disk) leaves the old set whole, never new maps beside an old maps.json.
  std::vector<io::FileSetEntry> files =
      material_export::texturedGltfFiles(maps, widthM, heightM, input.string());
  const json mapsDocument = mapsJson(result, maps, input.string());
  files.push_back({"maps.json", [&](const std::filesystem::path& path) {
                     fit::writeMaterialJson(path, mapsDocument);
                   }});
  io::replaceFileSet(output, kMapsFileSet, files);
  io.out << std::fixed << std::setprecision(1) << "fitted " << result.fitted << " of "
         << result.texels.size() << " texels (diffuse + anisotropic GGX; " << result.multiStart
         << " needed the multi-start fit) on " << result.threads << " threads in "
         << result.seconds << " s\n";
  if (failed > 0)
    io.out << failed << " texels not fitted: 0 in " << (output / material_export::kMaskPng).string()
           << ", named in maps.json\n";
  io.out << "wrote the maps and " << (output / material_export::kTexturedGltf).string() << " ("
         << result.tiltFitted << " texels with a fitted tilt in normal.png, "
         << result.fitted - result.tiltFitted << " flat: no specular lobe to tilt)\n";
  return 0;
}

}  // namespace slicecap::cli
