// `slicecap btf` end to end: a simulated woven session to the BTF directory, read back; bad
// options are usage errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/btf/btf_files.hpp"
#include "slicecap/io/abrdf_exr.hpp"

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
  const test::CliResult empty = test::runSlicecap({"btf", (dir / "btf").string(), "-o", out});
  EXPECT_EQ(empty.code, kExitFailure);
  EXPECT_NE(empty.err.find("no recording"), std::string::npos) << empty.err;
}

}  // namespace
}  // namespace slicecap::cli
