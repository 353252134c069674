// The prior's model file: every field round-trips, bad files and failed writes name the path and
// keep the old file, and training needs more channels than components.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../support/file_size_limit.hpp"
#include "../support/isotropic_training_tables.hpp"
#include "../support/test_support.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {
namespace {

using test::analyticTables;

TEST(PriorModelFile, RoundTripsEveryField) {
  const std::vector<Abrdf> tables = analyticTables();
  TrainingParams params;
  params.components = 4;
  const PriorModel model = trainPriorModel(tables, params, "four Blinn-Phong pairs");
  ASSERT_EQ(model.components(), 4);
  for (int k = 1; k < model.components(); ++k)
    EXPECT_LE(model.variance[k], model.variance[k - 1]) << "variances must decrease";
  const auto path = test::freshTempDir() / "p.bin";
  writePriorModel(path, model);
  const PriorModel back = readPriorModel(path);
  EXPECT_EQ(back.provenance, model.provenance);
  EXPECT_EQ(back.mean, model.mean);
  EXPECT_EQ(back.basis, model.basis);
  EXPECT_EQ(back.variance, model.variance);
  EXPECT_DOUBLE_EQ(back.residualVariance, model.residualVariance);
  EXPECT_DOUBLE_EQ(back.floorFraction, model.floorFraction);
}

TEST(PriorModelFile, TruncatedOrForeignFilesNameThePath) {
  const auto dir = test::freshTempDir();
  TrainingParams params;
  params.components = 2;
  writePriorModel(dir / "p.bin", trainPriorModel(analyticTables(), params));
  std::filesystem::resize_file(dir / "p.bin", 1000);
  std::ofstream(dir / "foreign.bin") << "not a prior at all";
  for (const char* name : {"p.bin", "foreign.bin", "absent.bin"}) {
    try {
      readPriorModel(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const PriorError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

TEST(PriorModelFile, AFailedWriteLeavesTheOldFile) {
  // prior-train over an existing prior on a full disk used to leave it truncated.
  const auto dir = test::freshTempDir();
  TrainingParams params;
  params.components = 2;
  const PriorModel model = trainPriorModel(analyticTables(), params);
  writePriorModel(dir / "p.bin", model);
  const auto size = std::filesystem::file_size(dir / "p.bin");
  try {
    const test::FileSizeLimit limit(4096);  // writes past 4 kB fail as on a full disk
    writePriorModel(dir / "p.bin", model);
    ADD_FAILURE() << "the failed write was not noticed";
  } catch (const PriorError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "p.bin").string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::filesystem::file_size(dir / "p.bin"), size);
  EXPECT_EQ(readPriorModel(dir / "p.bin").mean, model.mean);
  EXPECT_FALSE(std::filesystem::exists(dir / "p.bin.tmp"));
}

TEST(PriorModelFile, TrainingNeedsMoreChannelsThanComponents) {
  TrainingParams params;
  params.components = 30;
  const std::vector<Abrdf> tables = analyticTables();
  const std::vector<Abrdf> two(tables.begin(), tables.begin() + 2);
  EXPECT_THROW(trainPriorModel(two, params), PriorError);
}

}  // namespace
}  // namespace slicecap::prior
