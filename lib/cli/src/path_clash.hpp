// Refusing a command line whose output would overwrite one of its own inputs, or another of its
// outputs: `sample t.exr -o t.exr` must not destroy the table it reads.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace slicecap::cli {

/// \brief A path a command reads or writes and how the user named it, for the message: an option
/// ("-o", "--report") or "the input".
struct NamedPath {
  std::string role;
  std::filesystem::path path;
};

/// \brief Throws UsageError naming both roles and paths when an output is the same file as an
/// input or as another output (the same file: std::filesystem::equivalent when both exist, else
/// the same absolute path once `.`, `..` and symbolic links are resolved). Outputs that are not
/// regular files (a device or a pipe: -o /dev/null, /dev/stdout) are never replaced and may be
/// shared. Call it before anything is written.
void refuseClashingPaths(const std::vector<NamedPath>& inputs,
                         const std::vector<NamedPath>& outputs);

/// \brief The files a command reading the recordings in `directories` depends on: each one's
/// recording.json, its calibration file if it names one, and every frame. Only what a recording
/// lists: when it cannot be read, just its recording.json (the command then reports the problem
/// when it reads the recording).
std::vector<NamedPath> recordingInputs(const std::vector<std::filesystem::path>& directories);

}  // namespace slicecap::cli
