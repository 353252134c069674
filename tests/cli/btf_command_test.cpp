// `slicecap btf` end to end: a simulated woven session to the BTF directory, read back; the same
// from a texture store as slicecapd captures and exports it; bad options are usage errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/btf/btf_files.hpp"
#include "slicecap/btf/texture_capture.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/slice_csv.hpp"

namespace slicecap::cli {
namespace {

TEST(BtfCommand, WovenSessionToADirectoryWhoseTexelsShowTheWeave) {
  const auto dir = test::freshTempDir();
  const auto session = (dir / "session").string(), out = (dir / "btf").string();
  // 8 frames a sweep (4 with the LED on): the smallest session that reconstructs.
  ASSERT_EQ(test::runSlicecap({"simulate", "--material", "woven", "--session", session, "--frames",
                               "8", "--ideal"})
                .code,
            kExitOk);
  const test::CliResult r =
      test::runSlicecap({"btf", session, "-o", out, "--resolution", "4", "--threads", "2"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("4 x 4 texels of 10 mm, 8 slices"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("16 texels on 2 threads"), std::string::npos) << r.err;
  const btf::BtfTexture texture = btf::readBtfDirectory(out);
  ASSERT_EQ(texture.resolution(), 4);
  EXPECT_NO_THROW(io::readAbrdfExr(std::filesystem::path(out) / "average.exr"));
  // Texel (0, 0) covers the weft cell at x -20..-10, y 10..20 (red satin), texel (1, 0) a warp
  // cell (blue satin): summed over every direction, red leads in one and blue in the other.
  double red[2] = {0, 0}, blue[2] = {0, 0};
  for (int light = 0; light < 81; ++light)
    for (int view = 0; view < 81; ++view)
      for (std::size_t t = 0; t < 2; ++t) {
        red[t] += texture.value(light, view, t, 0);
        blue[t] += texture.value(light, view, t, 2);
      }
  EXPECT_GT(red[0], blue[0]);
  EXPECT_GT(blue[1], red[1]);
  std::ifstream manifest(std::filesystem::path(out) / btf::kBtfManifest);
  EXPECT_EQ(nlohmann::json::parse(manifest).at("failed_texels"), 0);

  EXPECT_EQ(test::runSlicecap({"btf", session, "-o", out, "--resolution", "0"}).code, kExitUsage);
  EXPECT_EQ(test::runSlicecap({"btf", session, "-o", out, "--method", "c"}).code, kExitUsage);
  // A folder without recordings (the BTF just written; into another folder: the same one as
  // input and output is bad usage).
  const test::CliResult empty =
      test::runSlicecap({"btf", (dir / "btf").string(), "-o", (dir / "btf2").string()});
  EXPECT_EQ(empty.code, kExitFailure);
  EXPECT_NE(empty.err.find("no recording"), std::string::npos) << empty.err;
}

TEST(BtfCommand, ATextureStoreAsSlicecapdExportsItGivesTheBtfOfItsRecordings) {
  namespace fs = std::filesystem;
  const auto dir = test::freshTempDir();
  const fs::path session = dir / "session", store = dir / "export" / "s1-texture";
  ASSERT_EQ(test::runSlicecap({"simulate", "--material", "woven", "--session", session.string(),
                               "--frames", "8", "--ideal"})
                .code,
            kExitOk);
  // What the daemon does with every frame of every sweep, and what `slicecap export` adds.
  SliceSet averageSlices;
  for (const fs::directory_entry& entry : fs::directory_iterator(session)) {
    const io::Recording header = io::readRecording(entry.path());
    btf::TextureSweep sweep(store, header.slice->id, header.camera,
                            {4, header.target.window, 5});
    const capture::RecordingResult result = capture::processRecording(
        entry.path(), {},
        [&](const hal::Frame& frame, const capture::FrameOutcome& outcome,
            const std::vector<capture::AmbientTerm>& ambient) { sweep.add(frame, outcome, ambient); });
    for (const SliceSample& sample : result.bins.combine())
      averageSlices.add(result.slice, sample);
  }
  const fs::path fromRecordings = dir / "btf-recordings", fromStore = dir / "btf-store";
  ASSERT_EQ(test::runSlicecap({"btf", session.string(), "-o", fromRecordings.string(),
                               "--resolution", "4", "--threads", "2"})
                .code,
            kExitOk);

  test::CliResult r = test::runSlicecap({"btf", store.string(), "-o", fromStore.string()});
  EXPECT_EQ(r.code, kExitFailure);  // no slices.csv yet
  EXPECT_NE(r.err.find("slices.csv: missing"), std::string::npos) << r.err;
  io::writeSliceCsv(store / "slices.csv", averageSlices);
  EXPECT_EQ(test::runSlicecap({"btf", store.string(), "-o", fromStore.string(), "--resolution", "8"})
                .code,
            kExitUsage);  // the capture fixed it
  r = test::runSlicecap({"btf", store.string(), "-o", fromStore.string(), "--threads", "2"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("4 x 4 texels of 10 mm, 8 slices from the captured texture"),
            std::string::npos)
      << r.err;

  const btf::BtfTexture want = btf::readBtfDirectory(fromRecordings);
  const btf::BtfTexture got = btf::readBtfDirectory(fromStore);
  ASSERT_EQ(got.resolution(), 4);
  // The store keeps texels as half floats, as the BTF itself: every texel's table the same to
  // within that rounding carried through the reconstruction.
  for (std::size_t texel = 0; texel < 16; ++texel)
    for (int c = 0; c < 3; ++c) {
      double sumWant = 0.0, sumGot = 0.0;
      for (int light = 0; light < 81; ++light)
        for (int view = 0; view < 81; ++view) {
          sumWant += want.value(light, view, texel, c);
          sumGot += got.value(light, view, texel, c);
        }
      EXPECT_NEAR(sumGot, sumWant, 0.005 * sumWant) << "texel " << texel << " channel " << c;
    }

  // The learned prior per texel, and for the average, named in btf.json and average.exr.
  const fs::path withPrior = dir / "btf-prior";
  r = test::runSlicecap(
      {"btf", store.string(), "-o", withPrior.string(), "--threads", "2", "--method", "prior"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("btf: the prior, 16 texels on 2 threads"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("with the anisotropy terms"), std::string::npos) << r.err;
  std::ifstream priorManifest(withPrior / btf::kBtfManifest);
  const nlohmann::json manifest = nlohmann::json::parse(priorManifest);
  EXPECT_EQ(manifest.at("method"), "prior");
  EXPECT_EQ(manifest.at("failed_texels"), 0);
  io::ExrAttributes attributes;
  io::readAbrdfExr(withPrior / "average.exr", &attributes);
  EXPECT_EQ(attributes["method"], "prior");
  EXPECT_EQ(btf::readBtfDirectory(withPrior).resolution(), 4);

  // A daemon's session folder, or its live texture inside, is not read (the export adds the
  // slices, and the daemon may still be writing).
  fs::create_directories(dir / "storage" / "s1");
  fs::rename(store, dir / "storage" / "s1" / "texture");
  std::ofstream(dir / "storage" / "s1" / "session.json") << "{}";
  std::ofstream(dir / "storage" / "s1" / "journal") << "";
  for (const fs::path& live : {dir / "storage" / "s1", dir / "storage" / "s1" / "texture"}) {
    r = test::runSlicecap({"btf", live.string(), "-o", fromStore.string()});
    EXPECT_EQ(r.code, kExitFailure) << live;
    EXPECT_NE(r.err.find("slicecap export"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace slicecap::cli
