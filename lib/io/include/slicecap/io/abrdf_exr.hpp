// ABRDF as OpenEXR: 81 x 81 RGB float32, row = light index, column = view index, BRDF in 1/sr.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::io {

/// \brief The `slicecap:*` header attributes of an ABRDF EXR, without the prefix. The writer always
/// sets layout = "bonn81", quantity = "brdf" and version; callers add e.g. "method", "material".
using ExrAttributes = std::map<std::string, std::string>;

/// \brief Writes `table` (ZIP compressed). Throws IoError naming the path on failure, which leaves
/// an old file at `path` as it was (written through a temporary), and for a table holding a
/// non-finite or negative value (naming the first one's light, view and channel): readAbrdfExr
/// refuses those.
void writeAbrdfExr(const std::filesystem::path& path, const Abrdf& table,
                   const ExrAttributes& attributes = {});

/// \brief Reads an ABRDF EXR; checks the 81 x 81 size, the R, G, B channels, `slicecap:layout` =
/// "bonn81", `slicecap:quantity` = "brdf" and finite, non-negative values (-0 is zero; a BRDF is
/// never negative and every reconstruction clips at 0). Throws IoError naming the path and
/// what is wrong (also that it is a directory). Fills `attributes` (if given) with every
/// `slicecap:*` string attribute.
Abrdf readAbrdfExr(const std::filesystem::path& path, ExrAttributes* attributes = nullptr);

}  // namespace slicecap::io
