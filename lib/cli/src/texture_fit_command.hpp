// `slicecap fit BTF_DIR -o MAPS_DIR`: the texture mode of `slicecap fit` (SVBRDF maps).
#pragma once

#include "slicecap/cli/args.hpp"
#include "slicecap/cli/command.hpp"

namespace slicecap::cli {

/// \brief Fits every texel of the BTF directory args.positional[0] and writes the maps, the
/// textured glTF and maps.json into -o (docs/material-fit.md "Texture mode"). Returns 0 when at
/// least one texel was fitted (the others named on io.err and in maps.json); throws UsageError
/// for an output inside the input (or the input inside it) and options that do not apply,
/// io::IoError naming a file of the BTF that cannot be read, fit::FitError when no texel could be
/// fitted (nothing is written then).
int runTextureFit(const ParsedArgs& args, Streams& io);

}  // namespace slicecap::cli
