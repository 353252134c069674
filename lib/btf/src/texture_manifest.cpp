// The texture store's manifest (texture.json): its layout, written and read.
#include "texture_manifest.hpp"

#include <stdexcept>
#include <utility>

#include "slicecap/btf/btf_error.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"
#include "texture_frame_file.hpp"

namespace slicecap::btf::manifest {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A whole number of the manifest that fits an int (checkLayout then checks its range): nlohmann's
// get<int>() of 1e300 is undefined behaviour, and of 128.7 quietly 128.
int wholeNumber(const json& j, const char* key, const fs::path& manifest) {
  const json& value = j.at(key);
  if (value.is_number_unsigned() && std::in_range<int>(value.get<std::uint64_t>()))
    return static_cast<int>(value.get<std::uint64_t>());
  if (value.is_number_integer() && !value.is_number_unsigned() &&
      std::in_range<int>(value.get<std::int64_t>()))
    return static_cast<int>(value.get<std::int64_t>());
  throw io::IoError(manifest.string() + ": " + key + ": expected a whole number, got " +
                    value.dump());
}

}  // namespace

json layoutJson(const TextureStoreLayout& layout) {
  return {{"format", "slicecap-texture-store"},
          {"version", 1},
          {"resolution", layout.resolution},
          {"frames_per_bin", layout.framesPerBin},
          {"bin_width_deg", kBinWidthDeg},
          {"window_mm",
           {{"x_min", layout.windowMm.xMinMm},
            {"y_min", layout.windowMm.yMinMm},
            {"x_max", layout.windowMm.xMaxMm},
            {"y_max", layout.windowMm.yMaxMm}}},
          {"texel_encoding", "float16le"},
          {"quantity", "brdf"},
          {"created_by", std::string("slicecap ") + kVersion}};
}

TextureStoreLayout readLayout(const fs::path& manifest) {
  const json j = io::parseJson(frame_file::readWhole(manifest), manifest.string());
  try {
    if (j.at("format") != "slicecap-texture-store")
      throw io::IoError(manifest.string() + ": format: not a slicecap texture store");
    if (j.at("version") != 1)
      throw io::IoError(manifest.string() + ": version: " + j.at("version").dump() +
                        " (this slicecap reads 1)");
    if (j.at("bin_width_deg").get<double>() != kBinWidthDeg)
      throw io::IoError(manifest.string() + ": bin_width_deg: only 15 is supported");
    // The frames' texels are read as these say: another encoding or quantity would be misread.
    if (j.at("texel_encoding") != "float16le")
      throw io::IoError(manifest.string() + ": texel_encoding: " + j.at("texel_encoding").dump() +
                        " (this slicecap reads \"float16le\")");
    if (j.at("quantity") != "brdf")
      throw io::IoError(manifest.string() + ": quantity: " + j.at("quantity").dump() +
                        " (this slicecap reads \"brdf\")");
    TextureStoreLayout layout;
    layout.resolution = wholeNumber(j, "resolution", manifest);
    layout.framesPerBin = wholeNumber(j, "frames_per_bin", manifest);
    const json& w = j.at("window_mm");
    layout.windowMm = {w.at("x_min").get<double>(), w.at("y_min").get<double>(),
                       w.at("x_max").get<double>(), w.at("y_max").get<double>()};
    return layout;
  } catch (const json::exception& e) {
    throw io::IoError(manifest.string() + ": " + e.what());
  }
}

void checkLayout(const TextureStoreLayout& layout) {
  TextureGrid(layout.resolution, layout.windowMm);  // throws for a bad resolution or window
  if (layout.framesPerBin < 1 || layout.framesPerBin > 64)
    throw BtfError("texture store: frames per bin must be in 1..64, not " +
                   std::to_string(layout.framesPerBin));
}

}  // namespace slicecap::btf::manifest
