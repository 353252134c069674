// Commands refuse, as bad usage, an output that is one of their inputs or another of their
// outputs, however the path is spelled; the input is left as it was.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"

namespace slicecap::cli {
namespace {

namespace fs = std::filesystem;
using Result = test::CliResult;

Result run(const std::vector<std::string>& args) {
  return test::runSlicecap(args);
}

std::string contentsOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `args`, expects a usage error whose message holds every one of `named`, and that `kept`
// is unchanged.
void expectRefused(const std::vector<std::string>& args, const std::vector<std::string>& named,
                   const fs::path& kept) {
  std::string line;
  for (const std::string& a : args)
    line += a + " ";
  SCOPED_TRACE(line);
  const std::string before = contentsOf(kept);
  const Result r = run(args);
  EXPECT_EQ(r.code, kExitUsage) << r.err;
  for (const std::string& text : named)
    EXPECT_NE(r.err.find(text), std::string::npos) << text << " not in: " << r.err;
  EXPECT_EQ(contentsOf(kept), before) << kept;
}

TEST(PathClash, AnOutputThatIsTheInputIsRefusedHoweverItIsSpelled) {
  const fs::path dir = test::freshTempDir();
  const std::string table = (dir / "t.exr").string(), csv = (dir / "same.csv").string();
  ASSERT_EQ(run({"generate", "satin-blue-45", "-o", table}).code, kExitOk);
  ASSERT_EQ(run({"sample", table, "-o", csv}).code, kExitOk);

  expectRefused({"sample", table, "-o", table}, {"-o " + table, "the input " + table}, table);
  expectRefused({"reconstruct", csv, "-o", csv}, {"-o " + csv, "the input " + csv}, csv);
  // Other spellings of the same file: a dot, a detour, a symbolic link.
  expectRefused({"reconstruct", csv, "-o", (dir / "." / "same.csv").string()}, {"-o"}, csv);
  fs::create_directories(dir / "sub");
  expectRefused({"reconstruct", csv, "-o", (dir / "sub" / ".." / "same.csv").string()}, {"-o"},
                csv);
  fs::create_symlink("t.exr", dir / "picture.png");
  expectRefused({"preview", table, "-o", (dir / "picture.png").string()}, {"picture.png"}, table);
  fs::create_directories(dir / "tables");
  ASSERT_EQ(run({"generate", "satin-blue-45", "-o", (dir / "tables" / "a.f32").string()}).code,
            kExitOk);
  expectRefused(
      {"prior-train", (dir / "tables").string(), "-o", (dir / "tables" / "a.f32").string()},
      {"a.f32"}, dir / "tables" / "a.f32");
  expectRefused({"eval", table, "--out", table}, {"--out " + table}, table);
  expectRefused({"simulate", "--material", table, "-o", table}, {"--material " + table}, table);
  // A different file is fine.
  EXPECT_EQ(run({"reconstruct", csv, "-o", (dir / "r.exr").string()}).code, kExitOk);
}

TEST(PathClash, AnOutputThatIsAFileOfARecordingOrTheSessionIsRefused) {
  // Only recording.json matters here: the check comes before the recordings are processed.
  const fs::path dir = test::freshTempDir();
  const fs::path recording = dir / "session" / "axial-30-30";
  fs::create_directories(recording);
  const fs::path manifest = recording / "recording.json";
  std::ofstream(manifest) << "{\"stands for\": \"a recording\"}\n";
  expectRefused({"process", recording.string(), "-o", manifest.string()},
                {"-o " + manifest.string(), "the recording file"}, manifest);
  expectRefused(
      {"calibrate", (dir / "elsewhere").string(), recording.string(), "-o", manifest.string()},
      {"-o " + manifest.string()}, manifest);
  expectRefused({"capture-offline", (dir / "session").string(), "-o", manifest.string()},
                {"-o " + manifest.string()}, manifest);
  expectRefused({"btf", (dir / "session").string(), "-o", (dir / "session").string()},
                {"-o " + (dir / "session").string()}, manifest);
}

TEST(PathClash, TwoOutputsOfOneCommandMayNotBeTheSameFile) {
  const fs::path dir = test::freshTempDir();
  const std::string svg = (dir / "x.svg").string();
  const Result target = run({"target", "-o", svg, "--json", svg});
  EXPECT_EQ(target.code, kExitUsage);
  EXPECT_NE(target.err.find("--json " + svg + " is the same file as -o " + svg), std::string::npos)
      << target.err;
  EXPECT_FALSE(fs::exists(svg));

  const std::string csv = (dir / "p.csv").string(), exr = (dir / "e.exr").string();
  const std::string missing = (dir / "no-recording").string();
  expectRefused({"process", missing, "-o", csv, "--report", csv}, {"--report " + csv, "-o " + csv},
                dir / "p.csv");
  fs::create_directories(dir / "session" / "r");
  std::ofstream(dir / "session" / "r" / "recording.json") << "{}";
  const std::string session = (dir / "session").string();
  expectRefused({"capture-offline", session, "-o", exr, "--slices", exr}, {"--slices " + exr},
                dir / "e.exr");
  expectRefused({"capture-offline", session, "-o", exr, "--report", exr}, {"--report " + exr},
                dir / "e.exr");
  // A device is written in place, never replaced: sharing /dev/null is not a clash (the
  // missing recording is then the failure).
  EXPECT_EQ(run({"process", missing, "-o", "/dev/null", "--report", "/dev/null"}).code,
            kExitFailure);
}

}  // namespace
}  // namespace slicecap::cli
