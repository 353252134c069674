// The capture pipeline's command-line options (gate tolerances, detector), shared by the commands
// that run recordings through it.
#pragma once

#include <filesystem>
#include <vector>

#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/cli/args.hpp"

namespace slicecap::cli {

/// \brief The settings the options give; UsageError for a value out of range.
capture::PipelineSettings pipelineSettingsOf(const ParsedArgs& args);

/// \brief --report, --elevation-tolerance, --max-residual, --min-markers, --decimation.
std::vector<OptionSpec> pipelineOptions();

/// \brief The recordings (directories holding recording.json) directly under a session
/// directory, sorted; io::IoError naming the session when it cannot be read or holds none.
std::vector<std::filesystem::path> sessionRecordings(const std::filesystem::path& session);

}  // namespace slicecap::cli
