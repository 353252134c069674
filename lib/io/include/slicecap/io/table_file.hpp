// Full 81 x 81 tables on disk: the raw .f32 of shared/data/nbrdf-bonn81, and EXR, chosen by
// extension.
#pragma once

#include <filesystem>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::io {

/// \brief Reads 81 * 81 * 3 little-endian float32 values [light][view][rgb], no header. Throws
/// IoError naming the path when it cannot be opened, is a directory, has another size, or holds a
/// non-finite or negative value (naming its light, view and channel).
Abrdf readF32Table(const std::filesystem::path& path);

/// \brief Writes the raw little-endian float32 layout. Throws IoError naming the path on failure,
/// which leaves an old file at `path` as it was (written through a temporary), and for a table
/// that readF32Table would refuse (a non-finite or negative value).
void writeF32Table(const std::filesystem::path& path, const Abrdf& table);

/// \brief A table from `.exr` (readAbrdfExr) or `.f32` (readF32Table); a directory or any other
/// extension throws IoError naming the path.
Abrdf readTable(const std::filesystem::path& path);

}  // namespace slicecap::io
