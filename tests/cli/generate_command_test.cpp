// `slicecap generate MATERIAL.json`: a fitted material's table is the one the fit judged, and a file
// that is not a completed fit is refused, naming it, with nothing written.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/command.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;

Result run(const std::vector<std::string>& args) { return test::runSlicecap(args); }

// slicecap compare's mean dE of `test` against `reference`.
double compareDeltaE(const std::filesystem::path& reference, const std::filesystem::path& test) {
  const Result r = run({"compare", reference.string(), test.string(), "--json"});
  EXPECT_EQ(r.code, kExitOk) << r.err;
  return nlohmann::json::parse(r.out)["delta_e"].get<double>();
}

// Fits the built-in `material`'s table and tabulates the fit; returns the fit's own reported dE.
double fitAndTabulate(const std::string& material, const std::filesystem::path& dir,
                      const std::string& fittedTable) {
  const auto truth = dir / "truth.exr";
  const auto fitted = dir / "fit.json";
  EXPECT_EQ(run({"generate", material, "-o", truth.string()}).code, kExitOk);
  const Result fit = run({"fit", truth.string(), "-o", fitted.string()});
  EXPECT_EQ(fit.code, kExitOk) << fit.err;
  const Result generated = run({"generate", fitted.string(), "-o", (dir / fittedTable).string()});
  EXPECT_EQ(generated.code, kExitOk) << generated.err;
  EXPECT_NE(generated.out.find("fit.json"), std::string::npos) << generated.out;
  std::ifstream in(fitted);
  return nlohmann::json::parse(in)["metrics"]["delta_e"].get<double>();
}

TEST(GenerateFittedMaterial, TheTableOfAGgxFitIsTheGgxTable) {
  // brushed-steel-30's lobe is along 30 deg with the alphas across it: a table built with the
  // alphas or the tangent read the wrong way round would be far from the truth.
  const auto dir = test::freshTempDir();
  const double fitDeltaE = fitAndTabulate("brushed-steel-30", dir, "fit.exr");
  EXPECT_LT(fitDeltaE, 0.01);
  EXPECT_LT(compareDeltaE(dir / "truth.exr", dir / "fit.exr"), 0.01);
}

TEST(GenerateFittedMaterial, TheTableIsWhatTheFitJudged) {
  // A Ward table GGX cannot match (dE ~3, docs/results/2026-12-02-material-fit.md): the tabulated
  // fit must be as far from the truth as the fit itself reported, in both table formats.
  const auto dir = test::freshTempDir();
  const double fitDeltaE = fitAndTabulate("satin-blue-45", dir, "fit.f32");
  EXPECT_GT(fitDeltaE, 1.0);
  EXPECT_NEAR(compareDeltaE(dir / "truth.exr", dir / "fit.f32"), fitDeltaE, 1e-6);
  ASSERT_EQ(run({"generate", (dir / "fit.json").string(), "-o", (dir / "fit.exr").string()}).code,
            kExitOk);
  EXPECT_NEAR(compareDeltaE(dir / "truth.exr", dir / "fit.exr"), fitDeltaE, 1e-6);
}

TEST(GenerateFittedMaterial, AJsonThatIsNotAFitIsRefusedNamingIt) {
  const auto dir = test::freshTempDir();
  std::ofstream(dir / "notes.json") << "{\"format\": \"something-else\"}";
  const Result r =
      run({"generate", (dir / "notes.json").string(), "-o", (dir / "t.exr").string()});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("notes.json"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.exr"));
}

TEST(GenerateFittedMaterial, AMissingJsonIsNamedNotTakenForAMaterialName) {
  const auto dir = test::freshTempDir();
  const Result r =
      run({"generate", (dir / "absent.json").string(), "-o", (dir / "t.exr").string()});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("absent.json"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("unknown material"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.exr"));
}

}  // namespace
}  // namespace slicecap::cli
