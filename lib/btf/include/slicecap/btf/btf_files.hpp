// The BTF on disk (docs/btf-format.md): a directory of UTIA-named half-float EXRs, the 81 x 81
// average ABRDF, PNG previews and a JSON manifest.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "slicecap/btf/btf_texture.hpp"
#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::btf {

/// \brief "tlTTT_plPPP_tvTTT_pvPPP": the UTIA name of a light and view direction (whole degrees,
/// three digits).
std::string utiaName(const Direction& light, const Direction& view);
/// \brief "tvTTT_pvPPP/tlTTT_plPPP_tvTTT_pvPPP.exr" of Bonn grid indices, relative to the BTF
/// directory.
std::filesystem::path imagePath(int light, int view);

/// \brief What the manifest (btf.json) records besides the layout.
struct BtfDescription {
  vision::RectMm windowMm;          ///< the window the texture covers (target frame)
  std::string method;               ///< e.g. "B"
  std::string source;               ///< e.g. the session directory's name
  std::string averageMethod = "B";  ///< how average.exr was reconstructed
  std::size_t failedTexels = 0;
};

/// \brief The light directions of the previews (seen from the view direction straight above).
std::vector<Direction> previewLights();

/// \brief Writes `directory` (created if needed; existing BTF files in it are replaced):
/// 6561 images tvTTT_pvPPP/tlTTT_plPPP_tvTTT_pvPPP.exr (N x N, R G B half, ZIP, BRDF 1/sr),
/// average.exr (the 81 x 81 average ABRDF as writeAbrdfExr writes it, `averageAttributes`
/// added), preview/tlTTT_plPPP_tv000_pv000.png (8-bit sRGB of BRDF x cos(theta_i), one exposure
/// for all) and btf.json. `threads` (0: all cores) write the images. Every file is written to a
/// temporary beside it and renamed into place when whole, so a failed or interrupted write leaves
/// the file it would replace as it was. Throws io::IoError naming the path that failed.
void writeBtfDirectory(const std::filesystem::path& directory, const BtfTexture& texture,
                       const Abrdf& average, const BtfDescription& description,
                       const io::ExrAttributes& averageAttributes = {}, int threads = 0);

/// \brief What a reader needs of btf.json.
struct BtfManifest {
  int resolution = 0;        ///< texels across the window
  vision::RectMm windowMm;   ///< the window the texture covers (target frame)
};

/// \brief Reads and checks `directory`/btf.json: `format` "slicecap-btf", `resolution` a whole
/// number in 1..1024, `window_mm` four finite numbers [x_min, y_min, x_max, y_max] with min < max,
/// `version` 1, `quantity` "brdf" and `unit` "1/sr" (a table of another quantity would be fitted
/// as a BRDF). Throws io::IoError naming the file and the field.
BtfManifest readBtfManifest(const std::filesystem::path& directory);

/// \brief Reads a directory written by writeBtfDirectory (its btf.json, checked by
/// readBtfManifest, and all 6561 images; the first image's size is checked before the texture's
/// memory is taken). Throws io::IoError naming the file that is missing, of another size or not
/// an image of the layout.
BtfTexture readBtfDirectory(const std::filesystem::path& directory);

/// \brief The manifest's file name.
inline constexpr const char* kBtfManifest = "btf.json";

}  // namespace slicecap::btf
