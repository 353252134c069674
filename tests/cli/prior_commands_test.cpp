// End-to-end: the prior through the command line, generate -> sample -> reconstruct --method prior
// -> isotropy -> prior-train, as a person runs them (several commands and lib/prior together).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"

namespace slicecap::prior {
namespace {

struct CliResult {
  int code;
  std::string out;
};

CliResult runCli(std::vector<std::string> args) {
  std::ostringstream out, err;
  const int code = cli::runCli(args, out, err);
  return {code, out.str() + err.str()};
}

TEST(PriorCli, ReconstructIsotropyAndTrainRun) {
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "t.f32").string(), slices = (dir / "s.csv").string();
  ASSERT_EQ(runCli({"generate", "blue-plastic", "-o", truth}).code, 0);
  ASSERT_EQ(runCli({"sample", truth, "-o", slices, "--diagonal-only"}).code, 0);
  EXPECT_EQ(
      runCli({"reconstruct", slices, "-o", (dir / "p.exr").string(), "--method", "prior"}).code, 0)
      << "diagonal-only slices are accepted";
  const std::string matte = (dir / "m.f32").string(), matteSlices = (dir / "m.csv").string();
  ASSERT_EQ(runCli({"generate", "matte-paint", "-o", matte}).code, 0);
  ASSERT_EQ(runCli({"sample", matte, "-o", matteSlices}).code, 0);
  const CliResult blended = runCli(
      {"reconstruct", matteSlices, "-o", (dir / "m.exr").string(), "--method", "prior", "--json"});
  ASSERT_EQ(blended.code, 0) << blended.out;
  const auto details = nlohmann::json::parse(blended.out)["prior"];
  EXPECT_TRUE(details["method_b_blended"].get<bool>()) << details;
  EXPECT_LT(details["prior_weight"].get<double>(), 1.0);
  const CliResult iso = runCli({"isotropy", slices});
  EXPECT_EQ(iso.code, 0);
  EXPECT_NE(iso.out.find("isotropic: the axial sweeps are not needed"), std::string::npos)
      << iso.out;
  const CliResult train = runCli({"prior-train", dir.string(), "-o", (dir / "p.bin").string()});
  EXPECT_EQ(train.code, 1) << "one table cannot give 16 components: " << train.out;
}

}  // namespace
}  // namespace slicecap::prior
