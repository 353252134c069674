// Writes the seed corpora of the reader targets (tests/fuzz/corpus/<target>/) with the project's
// own writers: small valid files, each under 20 kB. Run by hand when a format changes, after
// scripts/fuzz has configured build-fuzz:
//   cmake --build build-fuzz --target make_seeds
//   build-fuzz/tests/fuzz/make_seeds tests/fuzz/corpus
// The prior file of even one component is 52 kB, so its seeds are that file cut short after the
// header, the provenance and part of the mean.
#include <png.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "slicecap/btf/texture_store.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/prior/prior_model.hpp"
#include "slicecap/vision/target.hpp"

namespace {

namespace fs = std::filesystem;
using namespace slicecap;

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void save(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  std::printf("%s: %zu bytes\n", path.c_str(), bytes.size());
}

// A small target: a 12 mm window and four tags, so that its JSON stays small.
vision::TargetGeometry smallTarget() {
  vision::TargetParams params;
  params.windowMm = 12.0;
  params.bandMm = 6.0;
  params.markerMm = 8.0;
  params.markerGapMm = 2.0;
  params.marginMm = 2.0;
  return vision::buildTarget(params);
}

void priorSeeds(const fs::path& out, const fs::path& scratch) {
  prior::PriorModel model;
  model.floorFraction = 0.01;
  model.residualVariance = 1e-3;
  model.mean.assign(prior::kFeatureCount, -2.0f);
  model.variance = {4.0f};
  model.basis.assign(prior::kFeatureCount, 0.0f);
  model.basis[0] = 1.0f;
  model.provenance = "fuzz seed: one component";
  prior::writePriorModel(scratch / "prior.bin", model);
  const std::string whole = readAll(scratch / "prior.bin");
  const std::size_t header = 8 + 3 * 4 + 2 * 8 + 4 + model.provenance.size();
  save(out / "header-and-provenance.bin", whole.substr(0, header));
  save(out / "part-of-mean.bin", whole.substr(0, header + 4096));
}

io::Recording recordingHeader() {
  io::Recording r;
  r.createdBy = "make_seeds";
  r.camera.intrinsics = {64, 48, 60.0, 61.0, 31.5, 23.5};
  r.camera.distortion = {-0.05, 0.01, 0.001, -0.001, 0.0};
  r.slice = io::RecordedSlice{{SliceKind::Axial, {30, 75}}, 15.0};
  r.target = smallTarget();
  return r;
}

void recordingSeeds(const fs::path& out, const fs::path& scratch) {
  const Image frame{64, 48, 3, 8, std::vector<std::uint16_t>(64 * 48 * 3, 90)};
  {
    io::RecordingWriter writer(scratch / "rec", recordingHeader());
    writer.append(frame, {"", 1000, true, 5000.0, 1.0});
    writer.append(frame, {"", 34333, false, 5000.0, 2.5});
    save(out / "two-frames.json", readAll(scratch / "rec" / io::kRecordingManifest));
  }
  io::Recording calibrated = recordingHeader();
  calibrated.calibrationFile = "camera.json";
  calibrated.encoding = PixelEncoding::Linear16;
  calibrated.slice.reset();
  io::RecordingWriter writer(scratch / "cal", calibrated);
  io::writeJsonFileAtomically(scratch / "cal" / "camera.json", io::cameraToJson(calibrated.camera));
  save(out / "calibration-file.json", readAll(scratch / "cal" / io::kRecordingManifest));
}

void targetSeeds(const fs::path& out, const fs::path& scratch) {
  io::writeTargetJson(scratch / "target.json", smallTarget());
  save(out / "small.json", readAll(scratch / "target.json"));
}

void journalSeeds(const fs::path& out, const fs::path& scratch) {
  const SliceId axial{SliceKind::Axial, {30, 30}}, diagonal{SliceKind::Diagonal, {75, 75}};
  capture::SessionStore store = capture::SessionStore::create(scratch / "sessions", "s", "felt");
  store.recordSweepStarted(axial);
  for (int k = 0; k < 3; ++k)
    store.recordSample(axial, {1000 + 33000 * k,
                               std::uint64_t(k),
                               {30, 15.0 * k},
                               {30, 15.0 * k + 15},
                               Rgb{0.1, 0.2, 0.3 + k}});
  store.recordSweepStopped(axial);
  store.redo(axial);
  store.recordSweepStarted(diagonal);
  store.recordSample(diagonal, {200000, 7, {75, 350}, {75, 10}, Rgb::gray(0.5)});
  const std::string journal = readAll(scratch / "sessions" / "s" / "journal");
  save(out / "two-sweeps", journal);
  save(out / "torn-tail", journal.substr(0, journal.size() - 20));
}

void pngSeeds(const fs::path& out, const fs::path& scratch) {
  for (int depth : {8, 16}) {
    for (int channels = 1; channels <= 4; ++channels) {
      Image image{5, 3, channels, depth, std::vector<std::uint16_t>(5 * 3 * channels)};
      for (std::size_t i = 0; i < image.samples.size(); ++i)
        image.samples[i] = std::uint16_t((i * 37) % (depth == 8 ? 256 : 65536));
      const std::string name = "d" + std::to_string(depth) + "c" + std::to_string(channels);
      io::writePng(scratch / (name + ".png"), image);
      save(out / (name + ".png"), readAll(scratch / (name + ".png")));
    }
  }
  // What the project does not write but reads (a converted video's frames may be anything): a
  // 2-bit palette image with transparency, interlaced.
  std::FILE* file = std::fopen((scratch / "palette.png").c_str(), "wb");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, 6, 5, 2, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_ADAM7,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_color palette[4] = {{0, 0, 0}, {255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  png_set_PLTE(png, info, palette, 4);
  png_byte alpha[2] = {0, 128};
  png_set_tRNS(png, info, alpha, 2, nullptr);
  png_write_info(png, info);
  const int passes = png_set_interlace_handling(png);
  std::vector<png_byte> row(2, 0x1b);
  for (int pass = 0; pass < passes; ++pass)
    for (int y = 0; y < 5; ++y)
      png_write_row(png, row.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
  save(out / "palette-interlaced.png", readAll(scratch / "palette.png"));
}

void textureSeeds(const fs::path& out, const fs::path& scratch) {
  const btf::TextureStoreLayout layout{4, smallTarget().window, 5};
  btf::TextureStore store = btf::TextureStore::openOrCreate(scratch / "texture", layout);
  btf::TextureFrame frame;
  frame.sliceParameterDeg = 31.0;
  frame.cameraMm = {100.0, 20.0, 180.0};
  frame.lightMm = {-80.0, 10.0, 150.0};
  frame.texels.assign(4 * 4 * 3, 0.25f);
  frame.texels[5] = std::numeric_limits<float>::quiet_NaN();  // a texel the frame did not see
  store.add({SliceKind::Axial, {30, 30}}, frame);
  const std::string manifest = readAll(scratch / "texture" / btf::kTextureStoreManifest);
  std::string frameFile;
  for (const auto& entry : fs::recursive_directory_iterator(scratch / "texture"))
    if (entry.path().extension() == ".tex") frameFile = readAll(entry.path());
  save(out / "manifest-only", manifest);
  save(out / "one-frame", manifest + "\n--frame--\n" + frameFile);
  save(out / "one-sealed-frame",
       manifest + "\n--sealed frame--\n" + frameFile.substr(0, frameFile.size() - 4));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds CORPUS_FOLDER (tests/fuzz/corpus)\n");
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path scratch = fs::temp_directory_path() / "slicecap-make-seeds";
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  priorSeeds(out / "prior_model_fuzz", scratch);
  recordingSeeds(out / "recording_fuzz", scratch);
  targetSeeds(out / "target_json_fuzz", scratch);
  journalSeeds(out / "journal_fuzz", scratch);
  pngSeeds(out / "png_fuzz", scratch);
  textureSeeds(out / "texture_store_fuzz", scratch);
  fs::remove_all(scratch);
  return 0;
}
