// `slicecap btf`: a session's recordings, or the texture slicecapd captured, to a BTF directory
// (per-texel reconstruction), beside the average ABRDF.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>
#include <ostream>
#include <thread>

#include "path_clash.hpp"
#include "pipeline_options.hpp"
#include "slicecap/btf/btf_files.hpp"
#include "slicecap/btf/btf_reconstruction.hpp"
#include "slicecap/btf/texture_capture.hpp"
#include "slicecap/btf/texture_store.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/methods/methods.hpp"
#include "slicecap/prior/prior_location.hpp"

namespace slicecap::cli {
namespace {

using methods::MethodId;

// "b|a|prior": the methods btf::reconstructBtf solves a texel with (btf::kTexelMethods).
std::string texelMethodNames() {
  std::string names;
  for (MethodId id : btf::kTexelMethods)
    names += (names.empty() ? "" : "|") + methods::cliName(id);
  return names;
}

// One of the methods btf::reconstructBtf solves a texel with (btf::kTexelMethods).
MethodId parseTexelMethod(const std::string& name) {
  const std::optional<MethodId> id = methods::parseMethodName(name);
  if (!id || std::find(btf::kTexelMethods.begin(), btf::kTexelMethods.end(), *id) ==
                 btf::kTexelMethods.end())
    throw UsageError("--method must be " + methods::cliName(MethodId::B) + ", " +
                     methods::cliName(MethodId::A) + " or " + methods::cliName(MethodId::Prior));
  return *id;
}

int wholeNumber(const ParsedArgs& args, const std::string& name, int fallback, int lo, int hi) {
  const double v = args.number(name, fallback);
  if (v != static_cast<int>(v) || v < lo || v > hi)
    throw UsageError("--" + name + " must be a whole number in " + std::to_string(lo) + ".." +
                     std::to_string(hi));
  return static_cast<int>(v);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The texture and the window-average slices, from wherever they were captured.
struct CapturedTexture {
  btf::TextureGrid grid;
  std::vector<btf::SliceTexture> slices;
  SliceSet averageSlices;
};

// Recordings: every frame through the pipeline here.
CapturedTexture fromRecordings(const std::filesystem::path& session, const ParsedArgs& args,
                               Streams& io) {
  btf::TextureCaptureParams captureParams;
  captureParams.resolution = wholeNumber(args, "resolution", 128, 1, 1024);
  captureParams.framesPerBin = wholeNumber(args, "frames-per-bin", 5, 1, 64);
  // Bad options are usage errors before the session is even looked at.
  const capture::PipelineSettings settings = pipelineSettingsOf(args);
  const auto started = std::chrono::steady_clock::now();
  btf::SessionTexture captured =
      btf::captureRecordings(sessionRecordings(session), settings, captureParams,
                             [&](const std::string& line) { io.err << line << "\n"; });
  const btf::TextureGrid& grid = captured.texture.grid();
  io.err << "btf: " << grid.resolution() << " x " << grid.resolution() << " texels of "
         << grid.texelWidthMm() << " mm, " << captured.texture.slices().size()
         << " slices captured in " << secondsSince(started) << " s; texel bins "
         << captured.texture.memoryBytes() / 1e6 << " MB (peak "
         << captured.texture.peakMemoryBytes() / 1e6 << " MB)\n";
  return {grid, captured.texture.slices(), std::move(captured.averageSlices)};
}

// A texture store slicecapd captured (as `slicecap export` writes it, with slices.csv).
CapturedTexture fromStore(const std::filesystem::path& directory, const ParsedArgs& args,
                          Streams& io) {
  for (const char* fixed : {"resolution", "frames-per-bin"})
    if (args.value(fixed))
      throw UsageError(std::string("--") + fixed + " is fixed by the captured texture (" +
                       directory.string() + "/" + btf::kTextureStoreManifest + ")");
  // A daemon's live store is still written to: read an export of it.
  if (std::filesystem::exists(directory.parent_path() / "session.json") &&
      std::filesystem::exists(directory.parent_path() / "journal"))
    throw io::IoError(directory.string() +
                      ": the texture of a slicecapd session, still written by the daemon: "
                      "`slicecap export ID -o DIR` copies it to DIR/ID-texture; run slicecap btf "
                      "on that");
  const btf::TextureStore store = btf::TextureStore::open(directory, btf::StoreAccess::ReadOnly);
  for (const std::string& dropped : store.recovery().droppedFiles)
    io.err << "warning: a damaged texture frame is left out: " << dropped << "\n";
  const std::filesystem::path csv = directory / "slices.csv";
  if (!std::filesystem::exists(csv))
    throw io::IoError(csv.string() +
                      ": missing (`slicecap export` writes it beside the texture: the average "
                      "ABRDF is made from the session's window samples)");
  const auto started = std::chrono::steady_clock::now();
  CapturedTexture captured{store.grid(), store.combine(), io::readSliceCsv(csv)};
  io.err << "btf: " << captured.grid.resolution() << " x " << captured.grid.resolution()
         << " texels of " << captured.grid.texelWidthMm() << " mm, " << captured.slices.size()
         << " slices from the captured texture (" << store.frameCount() << " frames, "
         << store.storedBytes() / 1e6 << " MB) combined in " << secondsSince(started) << " s\n";
  for (const btf::SliceTexture& slice : captured.slices)
    io.err << toString(slice.slice) << ": " << store.filledBins(slice.slice) << " of "
           << slice.bins.size() << " bins\n";
  return captured;
}

// The per-texel reconstruction as the options ask for it, and the prior file it uses.
struct TexelReconstruction {
  btf::BtfReconstructionParams params;
  std::filesystem::path priorFile;  // with the prior: where it was found
};

// Throws UsageError on a bad --threads or --method; with the prior, whatever locating it throws.
TexelReconstruction texelReconstructionOf(const ParsedArgs& args) {
  TexelReconstruction texels;
  btf::BtfReconstructionParams& reconParams = texels.params;
  reconParams.threads = wholeNumber(args, "threads", 0, 0, 256);
  reconParams.methodB.isotropic = args.flag("isotropic");
  reconParams.prior.isotropicOnly = reconParams.methodB.isotropic;
  const MethodId method =
      args.value("method") ? parseTexelMethod(*args.value("method")) : MethodId::B;
  reconParams.method = method;
  // Found (or its absence named) before minutes of frames are processed; its path is said from
  // here, as the file may go while they are.
  if (method == MethodId::Prior) {
    texels.priorFile = prior::locatePriorModel();
    reconParams.priorModel = &prior::defaultPriorModel();
  }
  return texels;
}

// The texture from a captured texture store or from recordings; throws io::IoError naming a
// slicecapd session folder, which is to be exported first.
CapturedTexture loadTexture(const std::filesystem::path& session, const ParsedArgs& args,
                            Streams& io) {
  if (std::filesystem::exists(session / "texture" / btf::kTextureStoreManifest))
    throw io::IoError(session.string() +
                      ": a slicecapd session folder: `slicecap export ID -o DIR` writes its "
                      "texture with the window samples to DIR/ID-texture; run slicecap btf on that");
  return std::filesystem::exists(session / btf::kTextureStoreManifest)
             ? fromStore(session, args, io)
             : fromRecordings(session, args, io);
}

// The average ABRDF, exactly as capture-offline makes it (with the prior when the texels are).
methods::MethodRun averageAbrdf(const CapturedTexture& captured, const TexelReconstruction& texels,
                                Streams& io) {
  methods::MethodOptions averageOptions;
  averageOptions.isotropic = texels.params.methodB.isotropic;
  const MethodId method = texels.params.method;
  methods::MethodRun average =
      methods::findMethod(method == MethodId::Prior ? MethodId::Prior : MethodId::B)
          .run(captured.averageSlices, averageOptions);
  for (const std::string& warning : average.warnings)
    io.err << "warning: average: " << warning << "\n";
  return average;
}

void printReconstructionReport(const btf::BtfReconstructionReport& report,
                               const btf::BtfTexture& texture, const TexelReconstruction& texels,
                               const std::string& methodName, Streams& io) {
  const MethodId method = texels.params.method;
  io.err << "btf: " << (method == MethodId::Prior ? "the prior" : "Method " + methodName) << ", "
         << report.texels << " texels on " << report.threads << " threads in " << report.seconds
         << " s; texture " << texture.memoryBytes() / 1e6 << " MB\n";
  if (method == MethodId::Prior)
    io.err << "btf: prior " << texels.priorFile.string() << "; " << report.priorBlendedTexels
           << " texels blended with Method B (little directional "
           << "structure), " << report.priorAnisotropicTexels << " with the anisotropy terms\n";
  if (report.failedTexels > 0)
    io.err << "warning: " << report.failedTexels
           << " texels could not be reconstructed (left at zero); first: " << report.firstFailure
           << "\n";
  if (report.closedFormFits > 0)
    io.err << "note: " << report.closedFormFits
           << " lobe fits fell back to the closed form (Ceres did not converge)\n";
}

// What btf.json and average.exr's attributes say besides the images.
struct BtfOutput {
  std::filesystem::path directory, session;
  std::string methodName;  // the texels' method by its EXR name
  int threads = 0;
};

void writeBtf(const BtfOutput& output, const CapturedTexture& captured,
              const btf::BtfTexture& texture, const methods::MethodRun& average,
              const btf::BtfReconstructionReport& report, Streams& io) {
  const btf::TextureGrid& grid = captured.grid;
  const std::filesystem::path& session = output.session;
  const auto started = std::chrono::steady_clock::now();
  btf::BtfDescription description;
  description.windowMm = grid.window();
  description.method = output.methodName;
  description.averageMethod = average.exrMethodName;
  description.source = session.filename().string();
  description.failedTexels = report.failedTexels;
  btf::writeBtfDirectory(output.directory, texture, average.table, description,
                         {{"method", average.exrMethodName},
                          {"source", session.filename().string()},
                          {"samples", std::to_string(captured.averageSlices.sampleCount())}},
                         output.threads);
  io.err << "btf: wrote the images in " << secondsSince(started) << " s\n";
  io.out << "wrote a " << grid.resolution() << " x " << grid.resolution() << " BTF ("
         << Abrdf::kDirections * Abrdf::kDirections << " images), average.exr and previews to "
         << output.directory.string() << "\n";
}

int run(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path session = args.positional[0];
  const std::filesystem::path output = args.required("output");
  // The BTF's thousands of images in the session's (or the captured texture's) own folder.
  refuseClashingPaths({{"the input", session}}, {{"-o", output}});
  const TexelReconstruction texels = texelReconstructionOf(args);
  const CapturedTexture captured = loadTexture(session, args, io);
  const methods::MethodRun average = averageAbrdf(captured, texels, io);

  btf::BtfReconstructionReport report;
  const btf::BtfTexture texture =
      btf::reconstructBtf(captured.grid, captured.slices, texels.params, &report);
  // btf.json's "method": the texels' method by its EXR name, without the isotropic form (as
  // before the registry).
  const std::string methodName = methods::exrMethodValue(texels.params.method, false);
  printReconstructionReport(report, texture, texels, methodName, io);
  writeBtf({output, session, methodName, texels.params.threads}, captured, texture, average, report,
           io);
  return report.failedTexels == report.texels ? 1 : 0;
}

}  // namespace

Command btfCommand() {
  std::vector<OptionSpec> options = {
      {"output", 'o', "DIR", "the BTF directory (required; created, files in it replaced)"},
      {"resolution", 0, "N", "texels across the window (default 128)"},
      {"threads", 0, "N", "reconstruction and writing threads (default: all cores)"},
      {"method", 0, texelMethodNames(),
       "per-texel method: b (default), a (one shared RBF factorisation) or prior (the learned "
       "prior; also for average.exr)"},
      {"frames-per-bin", 0, "K", "frames a bin keeps for its per-texel median (default 5)"},
      {"isotropic", 0, "",
       "b and a: use the diagonal slices only; prior: fit without the anisotropy terms"}};
  for (auto& o : pipelineOptions())
    if (o.name != "report") options.push_back(o);
  return {{"btf",
           "SESSION_DIR|TEXTURE_DIR -o DIR [--resolution N] [--threads N] [--method " +
               texelMethodNames() + "] [options]",
           "Spatially varying capture: every recording under SESSION_DIR through the capture\n"
           "pipeline, and each accepted frame's window rectified to an N x N texture in the\n"
           "target plane (through the pose and the camera's distortion; per texel its own light\n"
           "and view direction, the LED-off frame subtracted and the fitted irradiance divided\n"
           "out), binned like the average sample (15 deg, per-texel median of up to K frames).\n"
           "Every texel is reconstructed (Method B, Method A or the prior) on all cores. Writes\n"
           "DIR as docs/btf-format.md describes: 6561 half-float EXRs tvTTT_pvPPP/tlTTT_plPPP_\n"
           "tvTTT_pvPPP.exr (N x N, BRDF 1/sr), average.exr (the 81 x 81 average ABRDF from the\n"
           "window samples, as capture-offline makes it, by the same method), preview/*.png (the\n"
           "texture from above under 8 lights) and btf.json. Memory: the texture takes\n"
           "6561 x N^2 x 6 bytes (N = 128: 645 MB).\n"
           "TEXTURE_DIR instead: the texture slicecapd captured on the box (texture_resolution),\n"
           "as `slicecap export` writes it (EXPORT/ID-texture, with the session's slices.csv);\n"
           "its resolution and frames per bin are those of the capture.",
           options, 1, 1},
          run};
}

}  // namespace slicecap::cli
