// `slicecap eval` and `slicecap preview`: reports, sheets, progress, and failures that cost only
// their own rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/cli.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/table_file.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;

Result run(const std::vector<std::string>& args) {
  return test::runSlicecap(args);
}

std::vector<std::string> linesOf(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  return lines;
}

TEST(EvalCommand, RbfSpecReachesMethodAAndTheUniformBaseline) {
  const Result r = run({"eval", "blue-plastic", "--methods", "a,uniform", "--json", "--quiet",
                        "--rbf", "kernel=r3,poly=linear,frame=absolute,gamma=4,r0=2"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  const Result plain = run({"eval", "blue-plastic", "--methods", "a,uniform", "--json", "--quiet"});
  ASSERT_EQ(plain.code, kExitOk) << plain.err;
  const nlohmann::json plainReport = nlohmann::json::parse(plain.out);
  ASSERT_EQ(report["means"].size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NE(report["means"][k]["rmse"].get<double>(),
              plainReport["means"][k]["rmse"].get<double>())
        << "the spec changed nothing for " << report["means"][k]["method"];
  }
}

TEST(EvalCommand, RejectsABadRbfSpecNamingTheKey) {
  for (const std::string spec :
       {"kernel=gauss", "poly=cubic", "r0=-1", "frame=up", "gamma=x", "shape=2", "kernel"}) {
    const Result r = run({"eval", "blue-plastic", "--methods", "a", "--rbf", spec});
    EXPECT_EQ(r.code, kExitUsage) << spec;
    EXPECT_NE(r.err.find("--rbf"), std::string::npos) << spec << ": " << r.err;
  }
}

TEST(EvalCommand, RbfValuesOutsideTheirRangeAreUsageErrorsNamingTheRange) {
  // r0=1e10 or gamma=1e10 gave all-zero interpolations, silently.
  for (const std::string spec : {"r0=1e10", "r0=5", "r0=0.001", "kernel=imq,r0=1e-300"}) {
    const Result r = run({"eval", "blue-plastic", "--methods", "uniform", "--rbf", spec});
    EXPECT_EQ(r.code, kExitUsage) << spec;
    EXPECT_NE(r.err.find("--rbf: r0 '"), std::string::npos) << spec << ": " << r.err;
    EXPECT_NE(r.err.find("is not a number in 0.01..4"), std::string::npos) << spec << ": " << r.err;
  }
  for (const std::string spec : {"gamma=1e10", "gamma=1e300", "gamma=0.5", "gamma=1e-300"}) {
    const Result r = run({"eval", "blue-plastic", "--methods", "uniform", "--rbf", spec});
    EXPECT_EQ(r.code, kExitUsage) << spec;
    EXPECT_NE(r.err.find("is not a number in 1..1000"), std::string::npos) << spec << ": " << r.err;
  }
  // At the ends of the ranges both still interpolate: most entries of a material whose BRDF is
  // positive everywhere stay positive (an all-zero interpolation has none; negatives overshot
  // between the centres are clipped to zero).
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "t.exr").string(), slices = (dir / "s.csv").string(),
                    points = (dir / "u.csv").string(), table = (dir / "out.exr").string();
  ASSERT_EQ(run({"generate", "blue-plastic", "-o", truth}).code, kExitOk);
  ASSERT_EQ(run({"sample", truth, "-o", slices}).code, kExitOk);
  ASSERT_EQ(run({"sample", truth, "-o", points, "--uniform", "13"}).code, kExitOk);
  for (const std::string spec : {"kernel=imq,r0=0.01", "r0=4", "r0=4,gamma=1000"}) {
    for (const auto& [method, input] : {std::pair{"a", slices}, std::pair{"uniform", points}}) {
      const Result r = run({"reconstruct", input, "-o", table, "--method", method, "--rbf", spec});
      ASSERT_EQ(r.code, kExitOk) << spec << ": " << r.err;
      const Abrdf result = io::readAbrdfExr(table);
      const std::span<const float> values = result.values();
      const auto positive =
          std::count_if(values.begin(), values.end(), [](float v) { return v > 0; });
      EXPECT_GT(positive, static_cast<std::ptrdiff_t>(values.size() / 2)) << method << " " << spec;
    }
  }
}

TEST(EvalCommand, WritesReportsAndASheetPerMaterial) {
  const auto dir = test::freshTempDir();
  const Result r = run({"eval", "satin-blue-45", "blue-plastic", "--methods", "b,uniform,halfway",
                        "--out", dir.string()});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.out.find("means over 2 materials"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("margin over the uniform baseline"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("eval 2/2 blue-plastic"), std::string::npos) << "progress: " << r.err;
  EXPECT_EQ(linesOf(dir / "report.csv").size(), 1u + 2 * 3);
  std::ifstream jsonFile(dir / "report.json");
  const nlohmann::json report = nlohmann::json::parse(jsonFile);
  ASSERT_EQ(report["means"].size(), 3u);
  EXPECT_EQ(report["means"][0]["method"], "b");
  EXPECT_EQ(report["means"][0]["materials"], 2);
  EXPECT_EQ(report["materials"][1]["samples"], 169) << "the uniform capture: 13 x 13 points";
  for (const char* sheet : {"satin-blue-45.png", "blue-plastic.png"}) {
    const io::PngImage png = io::readPng(dir / sheet);
    EXPECT_EQ(png.channels, 3);
    EXPECT_GT(png.width, 4 * 81) << "reference and three reconstructions side by side";
  }
}

TEST(EvalCommand, JsonGoesToStdoutAndQuietSilencesProgress) {
  const Result r = run({"eval", "matte-paint", "--methods", "b", "--json", "--quiet"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["materials"][0]["material"], "matte-paint");
  EXPECT_EQ(report["materials"][0]["delta_e"], 0.0) << "Lambertian: exact";
}

TEST(EvalCommand, ABadTableCostsOnlyItsOwnRows) {
  const auto dir = test::freshTempDir();
  const auto broken = dir / "broken.f32";
  std::ofstream(broken) << "not a table";
  const auto out = dir / "out";
  const Result r = run({"eval", broken.string(), "matte-paint", "--methods", "b", "--out",
                        out.string(), "--no-sheets"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("broken.f32"), std::string::npos) << r.err;
  const std::vector<std::string> csv = linesOf(out / "report.csv");
  ASSERT_EQ(csv.size(), 2u);
  EXPECT_EQ(csv[1].rfind("matte-paint,b,", 0), 0u) << csv[1];
  EXPECT_FALSE(std::filesystem::exists(out / "matte-paint.png")) << "--no-sheets";
}

// A table every method runs on but none can be compared with (no positive value: the metrics
// are relative to its maximum) fails each method's row, not the material's load: the failure is
// counted in the method's means row, on stderr and in the exit status.
TEST(EvalCommand, AMethodThatFailsIsCountedAndFailsTheRun) {
  const auto dir = test::freshTempDir();
  const auto dark = dir / "dark.f32";
  io::writeF32Table(dark, Abrdf());
  const Result r = run({"eval", dark.string(), "matte-paint", "--methods", "b", "--quiet"});
  EXPECT_EQ(r.code, kExitFailure) << r.out << r.err;
  EXPECT_NE(r.err.find("dark, method b: "), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("  b  failed: "), std::string::npos) << r.out;
  const std::size_t means = r.out.find("means over 2 materials");
  ASSERT_NE(means, std::string::npos) << r.out;
  const std::size_t meansRow = r.out.find("\n  b ", means);
  ASSERT_NE(meansRow, std::string::npos) << r.out;
  const std::string row = r.out.substr(meansRow + 1, r.out.find('\n', meansRow + 1) - meansRow - 1);
  EXPECT_NE(row.find("(1 failed)"), std::string::npos) << row;
  // The same run without the dark table succeeds: the exit status is the failure's.
  EXPECT_EQ(run({"eval", "matte-paint", "--methods", "b", "--quiet"}).code, kExitOk);
}

TEST(EvalCommand, BadArgumentsAreUsageErrorsOrNamed) {
  EXPECT_EQ(run({"eval"}).code, kExitUsage);
  Result r = run({"eval", "matte-paint", "--methods", "b,zz"});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.err.find("'zz'"), std::string::npos) << r.err;
  EXPECT_EQ(run({"eval", "matte-paint", "--methods", "b,b"}).code, kExitUsage);
  r = run({"eval", "no-such-material"});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("no-such-material"), std::string::npos) << r.err;
  const Result help = run({"eval", "--help"});
  EXPECT_NE(help.out.find("halfway"), std::string::npos) << "every registered method is listed";
}

TEST(EvalCommand, AMaterialGivenTwiceIsAUsageErrorNamingIt) {
  // It wrote its rows twice and counted twice in the means; two tables of one name would also
  // share one sheet.
  const auto dir = test::freshTempDir();
  Result r = run(
      {"eval", "blue-plastic", "blue-plastic", "--methods", "b", "--out", (dir / "out").string()});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.err.find("material 'blue-plastic' is given twice"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << "refused before anything runs: " << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  // The same name from a group and by itself, or from two files with one stem.
  EXPECT_EQ(run({"eval", "builtin:isotropic", "blue-plastic", "--methods", "b"}).code, kExitUsage);
  for (const char* folder : {"a", "b"}) {
    std::filesystem::create_directories(dir / folder);
    ASSERT_EQ(run({"generate", "matte-paint", "-o", (dir / folder / "paint.f32").string()}).code,
              kExitOk);
  }
  r = run({"eval", (dir / "a" / "paint.f32").string(), (dir / "b" / "paint.f32").string(),
           "--methods", "b"});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.err.find((dir / "b" / "paint.f32").string()), std::string::npos) << r.err;
}

TEST(PreviewCommand, WritesALayoutAndSpheres) {
  const auto dir = test::freshTempDir();
  const auto png = dir / "satin.png";
  const Result r = run({"preview", "satin-red-90", "-o", png.string()});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  const io::PngImage image = io::readPng(png);
  EXPECT_GT(image.width, 81 * 3);
  EXPECT_EQ(run({"preview", "satin-red-90", "-o", (dir / "x.jpg").string()}).code, kExitUsage);
  EXPECT_EQ(run({"preview", "satin-red-90"}).code, kExitUsage) << "-o is required";
}

}  // namespace
}  // namespace slicecap::cli
