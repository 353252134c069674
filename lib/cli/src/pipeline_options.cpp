// The capture pipeline's command-line options, shared by process, capture-offline and btf.
#include "pipeline_options.hpp"

#include <algorithm>
#include <string>

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::cli {

capture::PipelineSettings pipelineSettingsOf(const ParsedArgs& args) {
  capture::PipelineSettings settings;
  settings.elevationToleranceDeg =
      args.number("elevation-tolerance", settings.elevationToleranceDeg);
  settings.maxPoseResidualPx = args.number("max-residual", settings.maxPoseResidualPx);
  settings.minMarkers = static_cast<int>(args.number("min-markers", settings.minMarkers));
  settings.detector.decimation =
      static_cast<float>(args.number("decimation", settings.detector.decimation));
  const std::string ambient = args.value("ambient").value_or("both");
  if (ambient != "both" && ambient != "previous")
    throw UsageError("--ambient must be both or previous");
  settings.offlineTwoSidedAmbient = ambient == "both";
  if (const auto unseenMm = args.numberIn("room-light-unseen-mm", 0.0, 1000.0,
                                          "a distance in mm from 0 (off) to 1000"))
    settings.maxRoomLightDistanceMm = *unseenMm;
  if (!(settings.elevationToleranceDeg > 0) || !(settings.maxPoseResidualPx > 0) ||
      settings.minMarkers < 2)
    throw UsageError("--elevation-tolerance and --max-residual must be > 0, --min-markers >= 2");
  // The detector refuses (capture::CaptureError) what the library would crash on; as an option
  // that is bad usage, said here with the range.
  const float decimation = settings.detector.decimation;
  if (!(decimation >= capture::kMinDecimation && decimation <= capture::kMaxDecimation))
    throw UsageError("--decimation must be in " +
                     std::to_string(static_cast<int>(capture::kMinDecimation)) + ".." +
                     std::to_string(static_cast<int>(capture::kMaxDecimation)));
  return settings;
}

std::vector<OptionSpec> pipelineOptions() {
  return {{"report", 0, "FILE", "per frame pose, light, gate outcome; per bin its frames (JSON)"},
          {"elevation-tolerance", 0, "DEG", "reject frames this far off the view elevation (5)"},
          {"max-residual", 0, "PX", "reject poses with a larger RMS reprojection error (1.5)"},
          {"min-markers", 0, "N", "reject frames with fewer markers (4)"},
          {"decimation", 0, "D", "the AprilTag detector's quad decimation, 1..16 (2)"},
          {"ambient", 0, "MODE",
           "room light from the LED-off frames on both sides (both, default) or the one before "
           "at the same pixels, as slicecapd live (previous)"},
          {"room-light-unseen-mm", 0, "MM",
           "reject an LED-on frame whose room light changed between its LED-off frames while the "
           "nearer was taken more than MM away (room_light_unseen; 15 for frames dropped in a "
           "bright room; 0: off; default: the recording's own, which slicecapd writes when "
           "its room_light_unseen_mm is on, else off)"}};
}

std::vector<std::filesystem::path> sessionRecordings(const std::filesystem::path& session) {
  std::vector<std::filesystem::path> recordings;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(session, error))
    if (std::filesystem::exists(entry.path() / io::kRecordingManifest))
      recordings.push_back(entry.path());
  if (error) throw io::IoError(session.string() + ": " + error.message());
  if (recordings.empty())
    throw io::IoError(session.string() + ": no recording (a directory with " +
                      io::kRecordingManifest + ") inside");
  std::sort(recordings.begin(), recordings.end());
  return recordings;
}

}  // namespace slicecap::cli
