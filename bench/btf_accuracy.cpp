// Per-texel accuracy of the BTF mode (issue 7) on the virtual rig's woven material, from a clean
// rig and from a realistic hand-held one (8-bit sRGB, room light with LED alternation, jitter,
// blur, occlusion, markers out of view) written as recordings and read by the same code as
// `slicecap btf` (captureRecordings), with the room light from the LED-off frame before (as live)
// and from both sides; each texel through Method B and through the learned prior. A program, not a
// test: scripts/btf-accuracy.
// Usage: btf_accuracy [RESOLUTION=32] [FRAMES_PER_SWEEP=48]
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <tuple>

#include "slicecap/btf/btf_reconstruction.hpp"
#include "slicecap/btf/texture_capture.hpp"
#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"
#include "slicecap/sim/patterned_material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/simulate.hpp"

namespace {

using namespace slicecap;

// Per-texel errors of one reconstruction of the texture against the texels' own materials.
struct TexelErrors {
  double meanDeltaE = 0, meanRmse = 0, meanRelativeRmse = 0;
  int texels = 0, failedTexels = 0, closerToOwnMaterial = 0;
};

struct RunResult {
  TexelErrors methodB, prior;
  int filledBins = 0;
  eval::Metrics average, averagePrior;  ///< window average vs the mean material
};

TexelErrors texelErrors(const btf::TextureCapture& texture,
                        const btf::BtfReconstructionParams& params) {
  const auto woven = sim::makeWovenMaterial(10.0);
  const int resolution = texture.grid().resolution();
  btf::BtfReconstructionReport report;
  const btf::BtfTexture btf =
      btf::reconstructBtf(texture.grid(), texture.slices(), params, &report);
  TexelErrors result;
  result.failedTexels = static_cast<int>(report.failedTexels);
  const Abrdf warp = models::tabulate(woven->component(0));
  const Abrdf weft = models::tabulate(woven->component(1));
  for (int row = 0; row < resolution; ++row) {
    for (int column = 0; column < resolution; ++column) {
      const Eigen::Vector3d p = texture.grid().texelCentreMm(column, row);
      const bool isWarp = woven->firstWeightAt(p.x(), p.y()) > 0.5;
      const Abrdf table = btf.texel(texture.grid().index(column, row));
      const eval::Metrics own = eval::compare(isWarp ? warp : weft, table);
      const eval::Metrics other = eval::compare(isWarp ? weft : warp, table);
      result.meanRelativeRmse += own.relativeRmse;
      result.meanDeltaE += own.deltaE;
      result.meanRmse += own.rmse;
      result.closerToOwnMaterial += own.relativeRmse < other.relativeRmse;
      ++result.texels;
    }
  }
  result.meanRelativeRmse /= result.texels;
  result.meanDeltaE /= result.texels;
  result.meanRmse /= result.texels;
  return result;
}

// Per-texel errors (Method B, `slicecap btf`'s default, and the prior, `--method prior`) and the
// window average's (each method), against the woven material.
RunResult evaluate(const btf::TextureCapture& texture, const SliceSet& averageSlices) {
  RunResult result;
  result.methodB = texelErrors(texture, {});
  btf::BtfReconstructionParams priorParams;
  priorParams.method = methods::MethodId::Prior;
  priorParams.priorModel = &prior::defaultPriorModel();
  result.prior = texelErrors(texture, priorParams);
  const auto woven = sim::makeWovenMaterial(10.0);
  const Abrdf warp = models::tabulate(woven->component(0));
  const Abrdf weft = models::tabulate(woven->component(1));
  Abrdf meanTruth;
  for (std::size_t i = 0; i < meanTruth.values().size(); ++i)
    meanTruth.values()[i] = 0.5f * (warp.values()[i] + weft.values()[i]);
  result.average = eval::compare(meanTruth, recon::reconstructMethodB(averageSlices));
  result.averagePrior = eval::compare(
      meanTruth, prior::reconstructWithPrior(averageSlices, prior::defaultPriorModel()));
  result.filledBins = static_cast<int>(averageSlices.sampleCount());
  return result;
}

// The clean rig, in memory: every frame LED-on, no room light.
RunResult runClean(const sim::RigParams& rig, int resolution) {
  const auto woven = sim::makeWovenMaterial(10.0);
  const sim::FrameRenderer renderer(vision::defaultSimulatedCamera(), vision::defaultTarget(),
                                    woven, rig);
  capture::PipelineSettings settings;
  settings.requireAmbient = false;
  btf::TextureCapture texture(renderer.camera(), renderer.target().window, {resolution, 5, {}});
  SliceSet averageSlices;
  for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
    for (const ElevationPair& pair : kMeasuredPairs) {
      const SliceId slice{kind, pair};
      std::vector<sim::FramePlan> plans =
          sim::planSweep(slice, kAxialOffsetDeg, rig, renderer.camera(), renderer.target());
      const double exposureUs = sim::chooseExposureUs(renderer, rig, plans);
      capture::FramePipeline pipeline(renderer.target(), renderer.camera(), settings);
      capture::AzimuthBins bins(kind);
      texture.startSlice(slice);
      for (sim::FramePlan& plan : plans) {
        plan.exposureUs = std::round(exposureUs * plan.exposureScale);
        const sim::FrameScene scene{plan.exposurePoses,
                                    plan.lightMm,
                                    plan.ledOn,
                                    plan.exposureUs,
                                    plan.gain,
                                    plan.occluder,
                                    rig.seed * 7919u + static_cast<std::uint64_t>(plan.index)};
        const hal::Frame frame{
            renderer.render(scene),
            rig.encoding,
            {std::uint64_t(plan.index), plan.timestampUs, plan.exposureUs, plan.gain, plan.ledOn}};
        const capture::FrameOutcome outcome = pipeline.process(frame, slice);
        if (outcome.kind != capture::FrameOutcome::Kind::Sample) continue;
        texture.add(frame, outcome, {});
        bins.add(*outcome.sample);
      }
      texture.finishSlice();
      for (const SliceSample& s : bins.combine())
        averageSlices.add(slice, s);
    }
  }
  return evaluate(texture, averageSlices);
}

// A simulated session on disk through the same code as `slicecap btf` (captureRecordings), with
// the room light subtracted from the LED-off frames on both sides or (as live) the one before.
RunResult runSession(const std::vector<std::filesystem::path>& recordings, int resolution,
                     bool twoSidedAmbient) {
  capture::PipelineSettings settings;
  settings.poseAmbientFrames = true;
  settings.offlineTwoSidedAmbient = twoSidedAmbient;
  const btf::SessionTexture session =
      btf::captureRecordings(recordings, settings, {resolution, 5, {}});
  return evaluate(session.texture, session.averageSlices);
}

void print(const char* name, const RunResult& r) {
  std::printf("%s: %d of 192 bins filled\n", name, r.filledBins);
  for (const auto& [method, e, average] :
       {std::tuple{"Method B", r.methodB, r.average}, std::tuple{"prior", r.prior, r.averagePrior}})
    std::printf(
        "  %-8s per texel (%d texels, %d failed): mean dE %.2f, RMSE %.1f, relative RMSE %.3f, "
        "closer to own material %d; window average vs mean material: dE %.2f, RMSE %.1f, "
        "relative RMSE %.3f\n",
        method, e.texels, e.failedTexels, e.meanDeltaE, e.meanRmse, e.meanRelativeRmse,
        e.closerToOwnMaterial, average.deltaE, average.rmse, average.relativeRmse);
}

}  // namespace

int main(int argc, char** argv) {
  const int resolution = argc > 1 ? std::atoi(argv[1]) : 32;
  const int frames = argc > 2 ? std::atoi(argv[2]) : 48;
  if (resolution < 1 || resolution > 256 || frames < 8 || frames > 1000) {
    std::fprintf(stderr, "usage: btf_accuracy [RESOLUTION 1..256] [FRAMES_PER_SWEEP 8..1000]\n");
    return 2;
  }
  const auto woven = sim::makeWovenMaterial(10.0);
  eval::Metrics floor;
  for (const Abrdf& truth :
       {models::tabulate(woven->component(0)), models::tabulate(woven->component(1))}) {
    const eval::Metrics m =
        eval::compare(truth, recon::reconstructMethodB(recon::extractSlices(truth)));
    floor.deltaE += m.deltaE / 2, floor.rmse += m.rmse / 2,
        floor.relativeRmse += m.relativeRmse / 2;
  }
  std::printf("woven material (two Ward satins, 10 mm cells), %d x %d texels, %d frames a sweep\n",
              resolution, resolution, frames);
  std::printf(
      "Method B on ideal 168-sample slices of each material alone: dE %.2f, RMSE %.1f, "
      "relative RMSE %.3f\n",
      floor.deltaE, floor.rmse, floor.relativeRmse);
  sim::RigParams clean = sim::RigParams::ideal();
  clean.encoding = PixelEncoding::Linear16;
  clean.ambientIrradiance = 0.0;
  clean.alternateLed = false;
  clean.framesPerSlice = frames;
  const auto start = std::chrono::steady_clock::now();
  print("clean", runClean(clean, resolution));
  // The realistic session as recordings, as the box records them.
  const auto dir = std::filesystem::temp_directory_path() /
                   ("slicecap-btf-accuracy-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  sim::SweepSetup setup;
  setup.rig = sim::RigParams::realistic();
  setup.rig.framesPerSlice = frames;
  setup.materialSpec = "woven";
  const sim::FrameRenderer renderer(setup.camera, setup.target, woven, setup.rig);
  const std::vector<std::filesystem::path> recordings = sim::simulateSession(dir, renderer, setup);
  print("realistic, room light from the LED-off frame before (as live)",
        runSession(recordings, resolution, false));
  print("realistic, room light from both sides (slicecap btf's default)",
        runSession(recordings, resolution, true));
  std::filesystem::remove_all(dir);
  std::printf("(%.0f s)\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}
