// The evaluation report: means of per-material values, failures, worst cases, CSV and JSON.
#include "slicecap/eval/report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace slicecap::eval {
namespace {

EvaluationRow row(const char* material, const char* method, double deltaE, double rmse) {
  return {material, method, 168, {deltaE, rmse, 20.0 * std::log10(255.0 / rmse), 0.1}, 2.0, {}};
}

TEST(Report, MeansArePerMaterialMeansAndFailuresAreCountedApart) {
  std::vector<EvaluationRow> rows{row("gold", "b", 4.0, 10.0), row("gold", "a", 6.0, 20.0),
                                  row("chrome", "b", 2.0, 30.0), row("chrome", "a", 0, 0)};
  rows.back().error = "lobe fit failed";
  const std::vector<MethodSummary> s = summarise(rows, {"b", "a", "uniform"});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].materials, 2u);
  EXPECT_DOUBLE_EQ(s[0].mean.deltaE, 3.0);
  EXPECT_DOUBLE_EQ(s[0].mean.rmse, 20.0);
  // PSNR is the mean of per-material PSNRs (docs/method.md §6.1), not the PSNR of the mean RMSE.
  EXPECT_NEAR(s[0].mean.psnrDb,
              (20.0 * std::log10(255.0 / 10.0) + 20.0 * std::log10(255.0 / 30.0)) / 2.0, 1e-12);
  EXPECT_EQ(s[1].materials, 1u);
  EXPECT_EQ(s[1].failures, 1u);
  EXPECT_DOUBLE_EQ(s[1].mean.deltaE, 6.0);
  EXPECT_EQ(s[2].materials, 0u) << "a method without rows gets an empty summary";
}

TEST(Report, WorstMaterialsAreSortedByDeltaEAndCut) {
  std::vector<EvaluationRow> rows;
  for (int k = 0; k < 8; ++k)
    rows.push_back(row(("m" + std::to_string(k)).c_str(), "b", (k * 5) % 8, 10.0));
  const MethodSummary s = summarise(rows, {"b"}, 3).front();
  ASSERT_EQ(s.worst.size(), 3u);
  EXPECT_EQ(s.worst[0].metrics.deltaE, 7.0);
  EXPECT_EQ(s.worst[1].metrics.deltaE, 6.0);
  EXPECT_EQ(s.worst[2].metrics.deltaE, 5.0);
}

TEST(Report, CsvQuotesFieldsAndLeavesFailedMetricsEmpty) {
  std::ostringstream csv;
  writeReportCsvHeader(csv);
  writeReportCsvRow(csv, row("plain", "b", 1.5, 10.0));
  EvaluationRow failed = row("odd, \"name\"", "a", 0, 1);
  failed.error = "no slice 75/30";
  writeReportCsvRow(csv, failed);
  std::istringstream lines(csv.str());
  std::string header, first, second;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_EQ(header,
            "material,method,samples,delta_e,rmse,psnr_db,relative_rmse,peak_ratio,milliseconds,"
            "error");
  EXPECT_EQ(first.rfind("plain,b,168,1.5000,10.0000,", 0), 0u) << first;
  EXPECT_EQ(second, "\"odd, \"\"name\"\"\",a,168,,,,,,2.000,no slice 75/30");
}

TEST(Report, JsonHoldsRowsAndMeans) {
  std::vector<EvaluationRow> rows{row("gold", "b", 4.0, 10.0), row("gold", "a", 0, 1)};
  rows[1].error = "failed";
  const nlohmann::json j = reportJson(rows, summarise(rows, {"b", "a"}));
  ASSERT_EQ(j["materials"].size(), 2u);
  EXPECT_EQ(j["materials"][0]["delta_e"], 4.0);
  EXPECT_EQ(j["materials"][0]["peak_ratio"], 1.0);
  EXPECT_FALSE(j["materials"][1].contains("delta_e"));
  EXPECT_EQ(j["materials"][1]["error"], "failed");
  EXPECT_EQ(j["means"][0]["method"], "b");
  EXPECT_EQ(j["means"][0]["worst"][0]["material"], "gold");
  EXPECT_EQ(j["means"][1]["failures"], 1);
}

}  // namespace
}  // namespace slicecap::eval
