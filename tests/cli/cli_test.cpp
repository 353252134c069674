// The command line: exit codes, help, and the generate -> sample -> reconstruct -> compare
// pipeline.
#include "slicecap/cli/cli.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/slice_csv.hpp"

namespace slicecap::cli {
namespace {

using Result = test::CliResult;

Result run(const std::vector<std::string>& args) { return test::runSlicecap(args); }

TEST(Cli, HelpAndVersionSucceed) {
  EXPECT_EQ(run({"--help"}).code, kExitOk);
  EXPECT_NE(run({"--help"}).out.find("reconstruct"), std::string::npos);
  EXPECT_EQ(run({"--version"}).code, kExitOk);
  for (const char* command : {"reconstruct", "sample", "compare", "generate"}) {
    const Result r = run({command, "--help"});
    EXPECT_EQ(r.code, kExitOk) << command;
    EXPECT_NE(r.out.find("usage: slicecap"), std::string::npos) << command;
  }
}

TEST(Cli, BadUsageExitsWithTwo) {
  EXPECT_EQ(run({}).code, kExitUsage);
  EXPECT_EQ(run({"frobnicate"}).code, kExitUsage);
  EXPECT_EQ(run({"reconstruct"}).code, kExitUsage) << "missing SLICES.csv";
  EXPECT_EQ(run({"reconstruct", "a.csv"}).code, kExitUsage) << "missing -o";
  EXPECT_EQ(run({"reconstruct", "a.csv", "-o"}).code, kExitUsage) << "-o without a value";
  EXPECT_EQ(run({"reconstruct", "a.csv", "-o", "x.exr", "--method", "z"}).code, kExitUsage);
  EXPECT_EQ(run({"sample", "t.f32", "-o", "s.csv", "--step", "seven"}).code, kExitUsage);
  EXPECT_EQ(run({"sample", "t.f32", "-o", "s.csv", "--step", "7"}).code, kExitUsage);
  const Result r = run({"compare", "a.exr", "b.exr", "--colour"});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.err.find("unknown option --colour"), std::string::npos) << r.err;
  // An option given twice: the parser kept the last, so a first -o or --gltf was silently dropped.
  for (const std::vector<std::string>& twice :
       {std::vector<std::string>{"fit", "t.exr", "-o", "a.json", "-o", "b.json"},
        std::vector<std::string>{"fit", "t.exr", "-o", "a.json", "--gltf", "1.gltf", "--gltf=2.gltf"}}) {
    const Result t = run(twice);
    EXPECT_EQ(t.code, kExitUsage) << t.err;
    EXPECT_NE(t.err.find("given twice"), std::string::npos) << t.err;
  }
}

// A number option with a range (ParsedArgs::numberIn): text, NaN, an infinity and both sides of
// the range are usage errors naming the option, the value and what it takes, before any input is read.
TEST(Cli, ARangedNumberOptionNamesItsRange) {
  for (const char* value : {"-1", "1000.5", "nan", "inf", "5mm", ""}) {
    const Result r = run({"capture-offline", "no-session", "-o", "x.exr", "--room-light-unseen-mm", value});
    EXPECT_EQ(r.code, kExitUsage) << value;
    EXPECT_NE(r.err.find("--room-light-unseen-mm: '" + std::string(value) +
                         "' is not a distance in mm from 0 (off) to 1000"),
              std::string::npos) << r.err;
  }
}

// prior-cells per bin contradicts fitting every cell: said before the session is looked at.
TEST(Cli, PriorCellsPerBinWithEveryCellIsAUsageError) {
  for (const char* everyCell : {"--prior-every-cell", "--prior-cell-gls"}) {
    const Result r = run({"capture-offline", "no-session", "-o", "x.exr", "--method", "prior-cells",
                          "--prior-cells-per-bin", everyCell});
    EXPECT_EQ(r.code, kExitUsage) << everyCell;
    EXPECT_NE(r.err.find("--prior-cells-per-bin fits each bin's value, not every cell: not with " +
                         std::string(everyCell)),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("no-session"), std::string::npos) << r.err;
  }
}

TEST(Cli, FailuresExitWithOneAndNameTheInput) {
  const auto dir = test::freshTempDir();
  const Result r =
      run({"reconstruct", (dir / "missing.csv").string(), "-o", (dir / "x.exr").string()});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find("missing.csv"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.exr"));
}

TEST(Cli, ADirectoryGivenForAFileIsNamed) {
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "truth.exr").string();
  ASSERT_EQ(run({"generate", "satin-blue-45", "-o", truth}).code, kExitOk);
  for (const char* name : {"d.f32", "d.exr", "d.csv", "d"})
    std::filesystem::create_directories(dir / name);
  const auto at = [&](const char* name) { return (dir / name).string(); };
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"sample", at("d.f32"), "-o", at("s.csv")}, at("d.f32")},
      {{"compare", truth, at("d.exr")}, at("d.exr")},
      {{"compare", truth, at("d")}, at("d")},
      {{"reconstruct", at("d.csv"), "-o", at("r.exr")}, at("d.csv")},
      {{"simulate", "--material", "lambert", "-o", at("rec"), "--target", at("d")}, at("d")},
      {{"simulate", "--material", "lambert", "-o", at("rec"), "--camera", at("d")}, at("d")}};
  for (const auto& [args, directory] : cases) {
    SCOPED_TRACE(args[0] + " " + directory);
    const Result r = run(args);
    EXPECT_EQ(r.code, kExitFailure);
    EXPECT_NE(r.err.find(directory + ": is a directory"), std::string::npos) << r.err;
  }
}

TEST(Cli, ReconstructRefusesToWriteATableItsReaderWouldRefuse) {
  // One sample of 1e35 made Method B's table overflow to inf: the EXR was written, and every
  // reader then refused it.
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "truth.exr").string(), csv = (dir / "s.csv").string();
  ASSERT_EQ(run({"generate", "satin-blue-45", "-o", truth}).code, kExitOk);
  ASSERT_EQ(run({"sample", truth, "-o", csv}).code, kExitOk);
  std::string text;
  {
    std::ifstream in(csv);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // The third sample's b (the first lines are a comment and the header).
  std::size_t line = 0;
  for (int i = 0; i < 4; ++i)
    line = text.find('\n', line) + 1;
  const std::size_t b = text.rfind(',', text.find('\n', line)) + 1;
  text.replace(b, text.find('\n', line) - b, "1e35");
  std::ofstream(csv, std::ios::trunc) << text;
  const std::string out = (dir / "r.exr").string();
  const Result r = run({"reconstruct", csv, "-o", out});
  EXPECT_EQ(r.code, kExitFailure);
  EXPECT_NE(r.err.find(out + ": not written: a non-finite value at light"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, TheWholeOfflinePipelineRuns) {
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "truth.exr").string(), slices = (dir / "s.csv").string(),
                    result = (dir / "r.exr").string();
  ASSERT_EQ(run({"generate", "brushed-steel-30", "-o", truth}).code, kExitOk);
  ASSERT_EQ(run({"sample", truth, "-o", slices}).code, kExitOk);
  const Result rec = run({"reconstruct", slices, "-o", result, "--json"});
  ASSERT_EQ(rec.code, kExitOk) << rec.err;
  const auto summary = nlohmann::json::parse(rec.out);
  EXPECT_EQ(summary["samples"], 168);
  EXPECT_EQ(summary["all_fits_converged"], true);
  io::ExrAttributes attributes;
  io::readAbrdfExr(result, &attributes);
  EXPECT_EQ(attributes.at("method"), "B");
  const Result cmp = run({"compare", truth, result, "--json"});
  ASSERT_EQ(cmp.code, kExitOk) << cmp.err;
  const auto metrics = nlohmann::json::parse(cmp.out);
  EXPECT_GT(metrics["psnr_db"].get<double>(), 15.0);
  EXPECT_LT(metrics["delta_e"].get<double>(), 10.0);
}

TEST(Cli, IsotropicReconstructionFromDiagonalSlicesOnly) {
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "t.f32").string(), slices = (dir / "s.csv").string();
  ASSERT_EQ(run({"generate", "blue-plastic", "-o", truth}).code, kExitOk);
  ASSERT_EQ(run({"sample", truth, "-o", slices, "--diagonal-only"}).code, kExitOk);
  EXPECT_EQ(run({"reconstruct", slices, "-o", (dir / "a.exr").string()}).code, kExitFailure)
      << "the full method needs the axial slices";
  EXPECT_EQ(run({"reconstruct", slices, "-o", (dir / "i.exr").string(), "--isotropic"}).code,
            kExitOk);
}

TEST(Cli, ReconstructWithALostSliceNamesItWithItsSweepAndExportsWithThePrior) {
  // One lost slice stopped Method B with no table at all.
  const auto dir = test::freshTempDir();
  const std::string truth = (dir / "t.exr").string(), all = (dir / "s.csv").string(),
                    lost = (dir / "lost.csv").string(), out = (dir / "r.exr").string();
  ASSERT_EQ(run({"generate", "brushed-steel-30", "-o", truth}).code, kExitOk);
  ASSERT_EQ(run({"sample", truth, "-o", all}).code, kExitOk);
  const SliceSet sampled = io::readSliceCsv(all);
  SliceSet kept;
  for (const Slice& slice : sampled.slices())
    if (slice.id != SliceId{SliceKind::Diagonal, {75, 75}})
      for (const SliceSample& sample : slice.samples)
        kept.add(slice.id, sample);
  io::writeSliceCsv(lost, kept);
  const Result r = run({"reconstruct", lost, "-o", out});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_NE(r.err.find("missing:\n  diagonal 75/75: slicecap sweep start diagonal 75 75"),
            std::string::npos)
      << r.err;
  io::ExrAttributes attributes;
  io::readAbrdfExr(out, &attributes);
  EXPECT_EQ(attributes.at("method"), "prior");
  // Asked for by name, the prior gives the same table without the warning.
  const Result prior = run({"reconstruct", lost, "-o", (dir / "p.exr").string(), "--method",
                            "prior"});
  ASSERT_EQ(prior.code, kExitOk) << prior.err;
  EXPECT_EQ(prior.err.find("sweep start"), std::string::npos) << prior.err;
  EXPECT_EQ(test::maxAbsDifference(io::readAbrdfExr(out), io::readAbrdfExr(dir / "p.exr")), 0.0);
}

TEST(Cli, EveryOptionOfACommandIsInItsUsageLine) {
  // The usage line is what a person reads first (and docs/reference/cli.md shows it): an option
  // it leaves out must at least be announced by "[options]" or "...".
  for (const Command& command : allCommands()) {
    const std::string& synopsis = command.spec.synopsis;
    if (synopsis.find("[options]") != std::string::npos ||
        synopsis.find("...]") != std::string::npos || synopsis.ends_with("..."))
      continue;
    for (const OptionSpec& option : command.spec.options) {
      if (option.name == "help") continue;
      const bool named = synopsis.find("--" + option.name) != std::string::npos ||
                         (option.shortName && synopsis.find(std::string("-") + option.shortName +
                                                            " ") != std::string::npos);
      EXPECT_TRUE(named) << "slicecap " << command.spec.name << ": --" << option.name
                         << " is missing from the usage line '" << command.spec.synopsis << "'";
    }
  }
}

}  // namespace
}  // namespace slicecap::cli
