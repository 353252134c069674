// The texture store's manifest (texture.json): its layout, written and read.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "slicecap/btf/texture_store.hpp"

namespace slicecap::btf::manifest {

inline constexpr double kBinWidthDeg = 15.0;  // as the window-average bins (capture::AzimuthBins)

/// \brief The manifest's JSON.
nlohmann::json layoutJson(const TextureStoreLayout& layout);

/// \brief The layout a manifest describes. io::IoError naming the file and field when it is not
/// one this version reads.
TextureStoreLayout readLayout(const std::filesystem::path& manifest);

/// \brief Throws BtfError for a resolution, window or frames per bin out of range.
void checkLayout(const TextureStoreLayout& layout);

}  // namespace slicecap::btf::manifest
