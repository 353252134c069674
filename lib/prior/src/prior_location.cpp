// Run-time lookup of the prior file: environment, installed data directory, source tree.
#include "slicecap/prior/prior_location.hpp"

#include <cstdlib>
#include <string>
#include <system_error>

namespace slicecap::prior {

std::vector<std::filesystem::path> priorSearchPath() {
  std::vector<std::filesystem::path> paths;
  if (const char* file = std::getenv("SLICECAP_PRIOR"); file && *file) paths.emplace_back(file);
  paths.emplace_back(SLICECAP_PRIOR_INSTALL_PATH);
  paths.emplace_back(SLICECAP_PRIOR_SOURCE_PATH);
  return paths;
}

std::filesystem::path locatePriorModel() {
  // A prior asked for by name is that prior: falling back to another one would give results the
  // user did not ask for without a word.
  if (const char* file = std::getenv("SLICECAP_PRIOR"); file && *file) {
    const std::filesystem::path path(file);
    std::error_code error;
    if (std::filesystem::is_regular_file(path, error)) return path;
    throw PriorError("SLICECAP_PRIOR=" + path.string() + ": " +
                     (std::filesystem::is_directory(path, error)
                          ? "is a directory, not a prior file"
                          : "no such file") +
                     " (unset SLICECAP_PRIOR to use the installed or the source tree's prior)");
  }
  std::string tried;
  for (const std::filesystem::path& path : priorSearchPath()) {
    if (std::filesystem::is_regular_file(path)) return path;
    tried += (tried.empty() ? "" : ", ") + path.string();
  }
  throw PriorError("no prior file found (tried " + tried +
                   "); set SLICECAP_PRIOR to the file, or regenerate it with scripts/prior-train");
}

const PriorModel& defaultPriorModel() {
  static const PriorModel model = readPriorModel(locatePriorModel());
  return model;
}

}  // namespace slicecap::prior
