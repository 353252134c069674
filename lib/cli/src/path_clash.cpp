// Output paths against input paths: the same file however it is spelled.
#include "path_clash.hpp"

#include <stdexcept>
#include <system_error>

#include "slicecap/cli/args.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::cli {
namespace {

namespace fs = std::filesystem;

// An absolute path with `.`, `..` and the symbolic links of its existing part resolved.
fs::path resolved(const fs::path& path) {
  std::error_code error;
  fs::path result = fs::weakly_canonical(path, error);
  if (error) result = fs::absolute(path, error);
  return result.lexically_normal();
}

bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) {
    const bool same = fs::equivalent(a, b, error);
    if (!error) return same;
  }
  return resolved(a) == resolved(b);
}

// A device or a pipe (-o /dev/null): written in place, never replaced, so sharing it is harmless.
bool isSpecialFile(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  return fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

std::string describe(const NamedPath& named) {
  return named.role + " " + named.path.string();
}

}  // namespace

void refuseClashingPaths(const std::vector<NamedPath>& inputs,
                         const std::vector<NamedPath>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& output = outputs[i];
    if (isSpecialFile(output.path)) continue;
    for (const NamedPath& input : inputs)
      if (sameFile(output.path, input.path))
        throw UsageError(describe(output) + " is the same file as " + describe(input) +
                         ": it would be overwritten; write elsewhere");
    for (std::size_t j = 0; j < i; ++j)
      if (sameFile(output.path, outputs[j].path))
        throw UsageError(describe(output) + " is the same file as " + describe(outputs[j]) +
                         ": one would replace the other; give them different paths");
  }
}

std::vector<NamedPath> recordingInputs(const std::vector<fs::path>& directories) {
  const std::string role = "the recording file";
  std::vector<NamedPath> files;
  for (const fs::path& directory : directories) {
    files.push_back({role, directory / io::kRecordingManifest});
    try {
      const io::Recording recording = io::readRecording(directory);
      if (recording.calibrationFile)
        files.push_back({role, directory / *recording.calibrationFile});
      for (const io::RecordedFrame& frame : recording.frames)
        files.push_back({role, io::framePath(directory, frame)});
    } catch (const std::exception&) {
      // Reported, naming the field, when the command reads the recording.
    }
  }
  return files;
}

}  // namespace slicecap::cli
