// slicecap target: every format it writes reads back with the target's geometry; bad input is
// bad usage.
#include <gtest/gtest.h>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;

Result run(const std::vector<std::string>& args) { return test::runSlicecap(args); }

TEST(RigCommands, TargetWritesEveryFormatAndItsGeometry) {
  const auto dir = test::freshTempDir();
  for (const char* name : {"t.svg", "t.pdf", "t.png"}) {
    const Result r = run({"target", "-o", (dir / name).string(), "--dpi", "100"});
    ASSERT_EQ(r.code, kExitOk) << r.err;
    EXPECT_GT(std::filesystem::file_size(dir / name), 1000u) << name;
  }
  // 116 mm at 100 dpi.
  EXPECT_EQ(io::readPng(dir / "t.png").width, 457);
  ASSERT_EQ(run({"target", "--json", (dir / "default.json").string()}).code, kExitOk);
  EXPECT_EQ(io::readTargetJson(dir / "default.json"), vision::defaultTarget());
  ASSERT_EQ(run({"target", "--json", (dir / "w50.json").string(), "--window", "50"}).code, kExitOk);
  EXPECT_DOUBLE_EQ(io::readTargetJson(dir / "w50.json").window.widthMm(), 50.0);
  EXPECT_EQ(run({"target", "-o", (dir / "t.jpg").string()}).code, kExitUsage);
  EXPECT_EQ(run({"target", "-o", (dir / "t.png").string(), "--dpi", "10"}).code, kExitUsage);
}

}  // namespace
}  // namespace slicecap::cli
