// Where the shipped prior file is found at run time.
#pragma once

#include <filesystem>
#include <vector>

#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {

/// \brief The places searched, in order: $SLICECAP_PRIOR (a file), the installed file
/// (<datadir>/slicecap/prior.bin of the build's install prefix), the source tree's
/// data/prior/prior.bin (a build used in place).
std::vector<std::filesystem::path> priorSearchPath();

/// \brief $SLICECAP_PRIOR when it is set (PriorError naming it when it is not a file: a missing
/// file or a directory); else the first existing file of priorSearchPath(), PriorError listing
/// every path tried if none exists.
std::filesystem::path locatePriorModel();

/// \brief The model of locatePriorModel(), read once per process (readPriorModel's errors).
const PriorModel& defaultPriorModel();

}  // namespace slicecap::prior
