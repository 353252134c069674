// `slicecap simulate`: the virtual rig renders a sweep (or a whole session) as recordings + truth.
#include <chrono>
#include <filesystem>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/simulate.hpp"
#include "slicecap/sim/truth.hpp"

namespace slicecap::cli {
namespace {

sim::RigParams rigOf(const ParsedArgs& args) {
  if (args.flag("ideal") && args.flag("steady"))
    throw UsageError("--ideal and --steady exclude each other");
  sim::RigParams rig = args.flag("ideal")    ? sim::RigParams::ideal()
                       : args.flag("steady") ? sim::RigParams::steady()
                                             : sim::RigParams::realistic();
  const double frames = args.number("frames", rig.framesPerSlice);
  if (frames != static_cast<int>(frames)) throw UsageError("--frames must be a whole number");
  rig.framesPerSlice = static_cast<int>(frames);
  const double seed = args.number("seed", 1.0);
  if (seed < 0 || seed != static_cast<double>(static_cast<std::uint64_t>(seed)))
    throw UsageError("--seed must be a whole number >= 0");
  rig.seed = static_cast<std::uint64_t>(seed);
  rig.exposureUs = args.optionalNumber("exposure-us");
  rig.ambientIrradiance = args.number("ambient", rig.ambientIrradiance);
  rig.cameraDistanceMm = args.number("camera-distance", rig.cameraDistanceMm);
  rig.lightDistanceMm = args.number("light-distance", rig.lightDistanceMm);
  rig.alternateLed = !args.flag("no-led-alternation");
  const std::string metering = args.value("metering").value_or("brightest");
  if (metering != "brightest" && metering != "paper")
    throw UsageError("--metering must be brightest or paper");
  rig.metering =
      metering == "paper" ? sim::RigParams::Metering::Paper : sim::RigParams::Metering::Brightest;
  const double hdr = args.number("hdr", 1.0);
  if (hdr != static_cast<int>(hdr) || hdr < 1 || hdr > 3)
    throw UsageError("--hdr must be 1, 2 or 3");
  rig.maxExposureLevels = static_cast<int>(hdr);
  if (rig.maxExposureLevels > 1 && rig.exposureUs)
    throw UsageError("--hdr meters its exposures: give it without --exposure-us");
  const std::string encoding = args.value("encoding").value_or("srgb8");
  const auto parsed = parsePixelEncoding(encoding);
  if (!parsed) throw UsageError("--encoding must be srgb8 or linear16");
  rig.encoding = *parsed;
  std::string error;
  if (!rig.isValid(&error)) throw UsageError("simulate: " + error);
  return rig;
}

io::RecordedSlice sliceOf(const ParsedArgs& args) {
  const std::string kindText = args.value("slice").value_or("axial");
  const auto kind = parseSliceKind(kindText);
  if (!kind) throw UsageError("--slice must be axial or diagonal");
  auto elevation = [&](const char* name) {
    const double theta = args.number(name, 30.0);
    if (theta != static_cast<int>(theta) || theta < 0 || theta >= 90)
      throw UsageError(std::string("--") + name + " must be whole degrees in 0..89");
    return static_cast<int>(theta);
  };
  return {{*kind, {elevation("theta-i"), elevation("theta-v")}}, kAxialOffsetDeg};
}

// An unknown name or a bad model parameter is bad usage, as in `generate`; a table file that
// cannot be read is a failure naming the file (io::IoError passes through).
std::shared_ptr<const models::ReflectanceModel> materialOf(const std::string& spec) {
  try {
    return sim::loadMaterial(spec);
  } catch (const sim::MaterialError& e) {
    throw UsageError(std::string("simulate: --material: ") + e.what());
  }
}

int run(const ParsedArgs& args, Streams& io) {
  const auto output = args.value("output");
  const auto session = args.value("session");
  if (output.has_value() == session.has_value())
    throw UsageError(
        "simulate: give either -o RECORDING_DIR (one sweep) or --session DIR (all eight)");
  sim::SweepSetup setup;
  setup.rig = rigOf(args);
  setup.materialSpec = args.required("material");
  std::vector<NamedPath> inputs;
  if (std::filesystem::exists(setup.materialSpec))  // a table file, not a name or model spec
    inputs.push_back({"--material", setup.materialSpec});
  for (const char* option : {"target", "camera"})
    if (const auto file = args.value(option)) inputs.push_back({std::string("--") + option, *file});
  if (output) {
    const std::filesystem::path directory = *output;
    refuseClashingPaths(inputs, {{"-o", directory},
                                 {"-o", directory / io::kRecordingManifest},
                                 {"-o", directory / sim::kTruthFile}});
  } else {
    refuseClashingPaths(inputs, {{"--session", *session}});
  }
  if (const auto target = args.value("target")) setup.target = io::readTargetJson(*target);
  if (const auto camera = args.value("camera"))
    setup.camera = io::cameraFromJson(io::readJsonFile(*camera), *camera);
  const io::RecordedSlice slice = sliceOf(args);
  const auto started = std::chrono::steady_clock::now();
  const sim::FrameRenderer renderer(setup.camera, setup.target, materialOf(setup.materialSpec),
                                    setup.rig);
  int frames = 0;
  if (output) {
    frames = static_cast<int>(sim::simulateSweep(*output, slice, renderer, setup).frames.size());
    io.out << "wrote " << frames << " frames of " << toString(slice.id) << " to " << *output
           << " (with " << sim::kTruthFile << ")\n";
  } else {
    const auto recordings = sim::simulateSession(
        *session, renderer, setup, [&](const std::string& line) { io.err << line << "\n"; });
    for (const auto& recording : recordings)
      frames += static_cast<int>(io::readRecording(recording).frames.size());
    io.out << "wrote " << recordings.size() << " recordings (" << frames << " frames) under "
           << *session << "\n";
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  io.err << "simulate: " << frames << " frames in " << seconds << " s\n";
  return 0;
}

}  // namespace

Command simulateCommand() {
  return {
      {"simulate",
       "--material M (-o RECORDING_DIR [--slice axial|diagonal] [--theta-i DEG] [--theta-v DEG] "
       "| --session DIR) [options]",
       "The virtual rig: render what the camera sees while it sweeps one slice around the target\n"
       "lying on a material, lit by the LED, with a hand-held capture's imperfections (elevation\n"
       "and distance jitter, motion blur, sensor noise, room light, exposure changes, LED on/off\n"
       "alternation, the light arm over the window, markers out of view; --ideal: none). Writes\n"
       "a recording (recording.json + PNG frames) and truth.json (each frame's true pose, light,\n"
       "BRDF at the window centre). --session renders all eight slices as eight recordings.\n"
       "MATERIAL: a built-in name (slicecap generate --list), a .exr/.f32 table, or\n"
       "lambert:albedo=R,G,B | ward:diffuse=..,specular=..,ax=..,ay=..,tangent=DEG |\n"
       "ggx:diffuse=..,f0=..,ax=..,ay=..,tangent=DEG | woven[:cell=MM,fine=1] (a spatially\n"
       "varying plain weave of a blue satin along x and a red one along y, 10 mm cells, for\n"
       "slicecap btf; each pixel reads the weave over its footprint; fine=1: the threads finer\n"
       "than a pixel, half each everywhere, the weave's plain counterpart).",
       {{"material", 0, "M", "the material in the window (required)"},
        {"output", 'o', "DIR", "one sweep's recording directory (must not exist yet)"},
        {"session", 0, "DIR", "all eight sweeps, as DIR/axial-30-30 ... DIR/diagonal-75-75"},
        {"slice", 0, "KIND", "axial (default) or diagonal, with -o"},
        {"theta-i", 0, "DEG", "light elevation, with -o (default 30)"},
        {"theta-v", 0, "DEG", "camera elevation, with -o (default 30)"},
        {"frames", 0, "N", "frames a sweep (default 48: 24 with the LED on, 24 off)"},
        {"ideal", 0, "", "no imperfections: exact slice positions, no noise, blur or occlusion"},
        {"steady", 0, "", "the realistic sensor noise, none of the hand's imperfections"},
        {"encoding", 0, "E", "srgb8 (default) or linear16 frames"},
        {"exposure-us", 0, "US", "fixed exposure (default: metered, see --metering)"},
        {"metering", 0, "RULE", "brightest (default: window or references at 80 %) or paper"},
        {"hdr", 0, "N", "up to N (2, 3) metered exposures by LED pair (method.md 9.3)"},
        {"ambient", 0, "W/M2", "room light irradiance (default 0.3; the LED gives ~10)"},
        {"camera-distance", 0, "MM", "camera to window centre (default 300)"},
        {"light-distance", 0, "MM", "LED to window centre (default 300)"},
        {"no-led-alternation", 0, "", "the LED stays on in every frame"},
        {"seed", 0, "N", "random seed of the imperfections (default 1)"},
        {"target", 0, "FILE",
         "a target geometry JSON (slicecap target --json) instead of the default"},
        {"camera", 0, "FILE",
         "a camera JSON (recording.json's camera object) instead of the default"}},
       0,
       0},
      run};
}

}  // namespace slicecap::cli
