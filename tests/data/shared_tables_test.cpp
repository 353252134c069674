// End-to-end: golden test on measured materials, the reference implementation figures of
// docs/method.md §1.5 (skips without the measured tables).
#include <gtest/gtest.h>

#include "../support/test_support.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap {
namespace {

struct Golden {
  const char* table;
  double deltaE, rmse, psnrDb;
};

// docs/method.md §1.5: an independent implementation of the same reading (ideal slices, slice-sum,
// Method B).
constexpr Golden kGolden[] = {
    {"merl_nbrdf__blue-acrylic", 2.00, 18.95, 22.58},
    {"merl_nbrdf__chrome", 3.62, 37.46, 16.66},
    {"merl_nbrdf__gold-metallic-paint", 7.33, 19.60, 22.29},
    {"merl_nbrdf__green-latex", 1.65, 5.15, 33.90},
    {"merl_nbrdf__nickel", 2.57, 23.17, 20.83},
    {"merl_nbrdf__white-diffuse-bball", 2.36, 17.15, 23.45},
};

TEST(SharedTables, MethodBMatchesTheReferenceImplementation) {
  SLICECAP_REQUIRE_SHARED_DATA(dir);
  for (const Golden& g : kGolden) {
    const Abrdf truth = io::readTable(dir / (std::string(g.table) + ".f32"));
    recon::MethodBReport report;
    const Abrdf result = recon::reconstructMethodB(recon::extractSlices(truth), {}, &report);
    EXPECT_TRUE(report.allConverged()) << g.table;
    const eval::Metrics m = eval::compare(truth, result);
    // Two decimals as published.
    EXPECT_NEAR(m.deltaE, g.deltaE, 0.02) << g.table;
    EXPECT_NEAR(m.rmse, g.rmse, 0.02) << g.table;
    EXPECT_NEAR(m.psnrDb, g.psnrDb, 0.02) << g.table;
  }
}

TEST(SharedTables, EveryTableLoadsAndIsReciprocalWithinTheFitsTolerance) {
  SLICECAP_REQUIRE_SHARED_DATA(dir);
  int tables = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".f32") continue;
    ++tables;
    const Abrdf t = io::readTable(entry.path());
    EXPECT_GT(eval::cosWeightedMaximum(t), 0.0) << entry.path();
  }
  EXPECT_EQ(tables, 159);
}

}  // namespace
}  // namespace slicecap
