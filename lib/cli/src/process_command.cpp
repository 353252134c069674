// `slicecap process` (recordings -> slice CSV) and `slicecap capture-offline` (session -> EXR).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "path_clash.hpp"
#include "pipeline_options.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/cli/command_error.hpp"
#include "slicecap/methods/method_fallback.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/slice_csv.hpp"

namespace slicecap::cli {
namespace {

// Every recording's recording.json, read and checked before any frame is processed (a session's
// frames take minutes): a bad manifest (IoError naming the file and field), a recording without a
// slice, the same slice twice (bad usage). Returns them, in order, for processing.
std::vector<io::Recording> readRecordings(const std::vector<std::filesystem::path>& recordings) {
  std::vector<io::Recording> read;
  std::map<SliceId, std::filesystem::path> seen;
  for (const auto& directory : recordings) {
    read.push_back(io::readRecording(directory));
    const SliceId slice = capture::sliceOfRecording(directory, read.back());
    if (const auto previous = seen.find(slice); previous != seen.end())
      throw UsageError(directory.string() + ": slice " + toString(slice) +
                       " was already given by " + previous->second.string());
    seen[slice] = directory;
  }
  return read;
}

// "DIR (slice): rejected 20 blurred, 4 too_few_markers": why a recording gave no sample, the
// three most frequent reasons first.
std::string noSampleReason(const capture::RecordingResult& result) {
  std::vector<std::pair<capture::RejectReason, int>> reasons(result.rejections.begin(),
                                                             result.rejections.end());
  std::stable_sort(reasons.begin(), reasons.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string text = result.directory.string() + " (" + toString(result.slice) + "): ";
  if (reasons.empty()) return text + "no LED-on frame";
  text += "rejected";
  for (std::size_t k = 0; k < std::min<std::size_t>(reasons.size(), 3); ++k)
    text += (k ? ", " : " ") + std::to_string(reasons[k].second) + " " +
            std::string(toString(reasons[k].first));
  return text;
}

// How the window cells are read: --cell-texture (auto: the rule decides, or the action it names)
// and --cell-points-every (one sample per bin, or per that many degrees).
struct CellRules {
  capture::CellTextureRule texture;
  capture::CellSliceRule slices;
};

CellRules cellRulesOf(const ParsedArgs& args) {
  CellRules rules;
  const std::string mode = args.value("cell-texture").value_or("auto");
  if (mode != "auto") {
    rules.texture.forced = capture::parseCellTextureAction(mode);
    if (!rules.texture.forced)
      throw UsageError("--cell-texture: '" + mode + "' is not auto, as-read, normalise or centres");
  }
  // From a tenth of a degree (finer than the cells' own directions are known) to a bin's 15.
  if (const auto everyDeg = args.numberIn("cell-points-every", 0.1, 15.0,
                                          "a number of degrees from 0.1 to 15 (a bin)"))
    rules.slices.pointsEveryDeg = *everyDeg;
  return rules;
}

// What the recordings gave: the slices (each recording one slice) and, per recording that gave
// no sample, why (noSampleReason).
struct Processed {
  SliceSet slices;
  std::vector<std::string> withoutSamples;
};

// Reads and checks every recording (readRecordings), then runs each, printing its summary.
Processed processAll(const std::vector<std::filesystem::path>& recordings,
                     const capture::PipelineSettings& settings,
                     const CellRules& cellRules, Streams& io,
                     nlohmann::json* report) {
  const std::vector<io::Recording> read = readRecordings(recordings);
  Processed processed;
  for (std::size_t k = 0; k < recordings.size(); ++k) {
    capture::RecordingResult result = capture::processRecording(recordings[k], read[k], settings);
    const capture::CellTexture texture =
        capture::addSweepSlices(processed.slices, result.slice, result.bins, cellRules.texture,
                                cellRules.slices);
    const int samples = static_cast<int>(
        std::count_if(result.outcomes.begin(), result.outcomes.end(),
                      [](const auto& o) { return o.kind == capture::FrameOutcome::Kind::Sample; }));
    io.err << toString(result.slice) << " (" << recordings[k].string()
           << "): " << result.bins.filledCount() << " of " << result.bins.binCount() << " bins, "
           << samples << " samples, " << result.ambientFrames << " ambient";
    for (const auto& [reason, count] : result.rejections)
      io.err << ", " << count << " " << reason;
    if (!result.roomLightSubtracted)
      io.err << "; room light not subtracted: the LED is on in every frame";
    if (result.roomLightUnseenMm)
      io.err << "; room_light_unseen gate at " << *result.roomLightUnseenMm << " mm";
    io.err << "\n";
    if (texture.framesUsed > 0) io.err << "  " << texture.describe() << "\n";
    if (result.bins.filledCount() == 0) processed.withoutSamples.push_back(noSampleReason(result));
    if (report) {
      nlohmann::json entry = result.toJson(texture);
      if (texture.framesUsed > 0) entry["cell_texture"] = capture::toJson(texture);
      (*report)["recordings"].push_back(std::move(entry));
    }
  }
  return processed;
}

// No sample at all is a failure naming every recording and its main rejections (the report, if
// asked for, is written before: it holds every frame's reason); some recordings without samples
// are a warning naming them, and the others' samples are kept.
void refuseNoSamples(const Processed& processed, const std::optional<std::string>& reportPath,
                     const std::filesystem::path& output, Streams& io) {
  if (processed.slices.sampleCount() == 0) {
    std::string message = "no recording gave a sample, " + output.string() + " not written:";
    for (const std::string& reason : processed.withoutSamples)
      message += "\n  " + reason;
    if (reportPath) message += "\n  (every frame's reason is in " + *reportPath + ")";
    throw CommandError(message);
  }
  for (const std::string& reason : processed.withoutSamples)
    io.err << "warning: no sample from " << reason << "\n";
}

void writeReport(const std::filesystem::path& path, const nlohmann::json& report) {
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << report.dump(1) << "\n"; });
}

int runProcess(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path output = args.required("output");
  std::vector<std::filesystem::path> recordings(args.positional.begin(), args.positional.end());
  nlohmann::json report = {{"recordings", nlohmann::json::array()}};
  const auto reportPath = args.value("report");
  std::vector<NamedPath> outputs = {{"-o", output}};
  if (reportPath) outputs.push_back({"--report", *reportPath});
  if (const auto csv = args.value("cell-slices")) outputs.push_back({"--cell-slices", *csv});
  refuseClashingPaths(recordingInputs(recordings), outputs);
  const Processed processed =
      processAll(recordings, pipelineSettingsOf(args), cellRulesOf(args), io,
                 reportPath ? &report : nullptr);
  if (reportPath) writeReport(*reportPath, report);
  refuseNoSamples(processed, reportPath, output, io);
  const SliceSet& slices = processed.slices;
  io::writeSliceCsv(output, slices);
  if (const auto csv = args.value("cell-slices")) io::writeSliceCsv(*csv, slices.cellReading());
  io.out << "wrote " << slices.sampleCount() << " samples in " << slices.slices().size()
         << " slices to " << output.string() << "\n";
  return 0;
}

// The method's options: a contradiction is a usage error before the session is read.
methods::MethodOptions methodOptionsOf(const ParsedArgs& args) {
  methods::MethodOptions options;
  options.isotropic = args.flag("isotropic");
  if (args.flag("prior-cells-per-bin") &&
      (args.flag("prior-every-cell") || args.flag("prior-cell-gls")))
    throw UsageError(
        "--prior-cells-per-bin fits each bin's value, not every cell: not with " +
        std::string(args.flag("prior-cell-gls") ? "--prior-cell-gls" : "--prior-every-cell"));
  options.priorFitsEveryCell = !args.flag("prior-cells-per-bin");
  options.priorCellFrameEffect = args.flag("prior-cell-gls");
  return options;
}

int runCaptureOffline(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path session = args.positional[0];
  const std::filesystem::path output = args.required("output");
  // Bad options are usage errors before the session is even looked at.
  const capture::PipelineSettings settings = pipelineSettingsOf(args);
  const CellRules cellRules = cellRulesOf(args);
  const methods::Method& method = methods::findMethod(
      args.value("method").value_or(methods::cliName(methods::MethodId::B)));
  const methods::MethodOptions options = methodOptionsOf(args);
  const std::vector<std::filesystem::path> recordings = sessionRecordings(session);
  nlohmann::json report = {{"recordings", nlohmann::json::array()}};
  const auto reportPath = args.value("report");
  std::vector<NamedPath> outputs = {{"-o", output}};
  if (const auto csv = args.value("slices")) outputs.push_back({"--slices", *csv});
  if (const auto csv = args.value("cell-slices")) outputs.push_back({"--cell-slices", *csv});
  if (reportPath) outputs.push_back({"--report", *reportPath});
  refuseClashingPaths(recordingInputs(recordings), outputs);
  const Processed processed =
      processAll(recordings, settings, cellRules, io, reportPath ? &report : nullptr);
  if (reportPath) writeReport(*reportPath, report);
  refuseNoSamples(processed, reportPath, output, io);
  const SliceSet& slices = processed.slices;
  if (const auto csv = args.value("slices")) io::writeSliceCsv(*csv, slices);
  if (const auto csv = args.value("cell-slices")) io::writeSliceCsv(*csv, slices.cellReading());
  const methods::MethodRun result = methods::runMethodOrPrior(method, slices, options);
  // A method on the cells' reading read its samples, not the window centres.
  const std::size_t samples = methods::readsCellSamples(method.id)
                                  ? slices.cellReading().sampleCount()
                                  : slices.sampleCount();
  io::writeAbrdfExr(output, result.table,
                    {{"method", result.exrMethodName},
                     {"source", session.filename().string()},
                     {"samples", std::to_string(samples)}});
  for (const std::string& warning : result.warnings)
    io.err << "warning: " << warning << "\n";
  io.out << "reconstructed " << samples << " samples in " << slices.slices().size()
         << " slices with method " << result.exrMethodName << "; wrote " << output.string() << "\n";
  return 0;
}

// How both commands read the window's cells (cellRulesOf).
std::vector<OptionSpec> cellRuleOptions() {
  return {{"cell-texture", 0, "MODE",
           "the cells' reading of a textured window: auto (default), as-read, normalise or "
           "centres (docs/method.md 9.4)"},
          {"cell-points-every", 0, "DEG",
           "the cells' reading: one sample per DEG (0.1 to 15) of each slice's parameter, not one "
           "per bin (docs/method.md 9.4)"}};
}

}  // namespace

Command processCommand() {
  std::vector<OptionSpec> options = {
      {"output", 'o', "SLICES.csv", "the slice CSV (required)"},
      {"cell-slices", 0, "FILE",
       "also write the slice CSV valued from the window cells (docs/method.md 9.4)"},
};
  for (auto& o : cellRuleOptions()) options.push_back(o);
  for (auto& o : pipelineOptions())
    options.push_back(o);
  return {{"process", "RECORDING... -o SLICES.csv [--report report.json] [options]",
           "Run recorded sweeps through the capture pipeline: detect the tag36h11 markers, the\n"
           "camera pose from all their corners, the light direction (nominal elevation, azimuth\n"
           "from the slice; the point-light fit to the white references when it is certain),\n"
           "the gate (rejections: too_few_markers, elevation_off, blurred, window_clipped,\n"
           "window_occluded, pose_residual, no_ambient_frame, room_light_unseen, bad_frame;\n"
           "with --ambient previous, as live, also detection_deferred), the window's BRDF\n"
           "(the room light subtracted: the LED-off frames before and after, each at its own\n"
           "pose, interpolated where the camera was; divided by the fitted irradiance), 15 deg\n"
           "azimuth bins combined by median (an HDR recording's levels merged per cell instead,\n"
           "with the room light of each level: docs/method.md 9.3). One recording per slice; its\n"
           "slice comes from recording.json.\n"
           "Prints per slice the bins filled and the rejections by reason on stderr; no sample\n"
           "from any recording is a failure naming them (the report is still written).",
           options, 1, 64},
          runProcess};
}

Command captureOfflineCommand() {
  std::vector<OptionSpec> options = {
      {"output", 'o', "OUT.exr", "the reconstructed ABRDF (required)"},
      {"method", 0, "NAME",
       "reconstruction method (default " + methods::cliName(methods::MethodId::B) + ")"},
      {"isotropic", 0, "", "use the diagonal slices only"},
      {"slices", 0, "FILE", "also write the slice CSV"},
      {"cell-slices", 0, "FILE",
       "also write the slice CSV valued from the window cells (what b-cells reads)"},
      {"prior-every-cell", 0, "",
       "prior-cells fits every window cell as a point, one frame's cells as a group (the "
       "default; docs/method.md 9.4)"},
      {"prior-cells-per-bin", 0, "",
       "prior-cells fits each bin's value from the cells instead of every cell (a comparison)"},
      {"prior-cell-gls", 0, "",
       "as --prior-every-cell, one frame's cells fitted with a random frame effect instead "
       "(a comparison: docs/method.md 9.4)"},
};
  for (auto& o : cellRuleOptions()) options.push_back(o);
  for (auto& o : pipelineOptions())
    options.push_back(o);
  return {{"capture-offline", "SESSION_DIR -o OUT.exr [--method b] [options]",
           "slicecap process on every recording under SESSION_DIR (e.g. what simulate --session\n"
           "or a capture session wrote), then slicecap reconstruct: the session to the EXR in\n"
           "one step.",
           options, 1, 1},
          runCaptureOffline};
}

}  // namespace slicecap::cli
