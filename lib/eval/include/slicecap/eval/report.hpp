// The evaluation report: one row per material and method, means and worst cases per method, and
// its CSV and JSON forms.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slicecap/eval/metrics.hpp"

namespace slicecap::eval {

/// \brief One material reconstructed by one method; `error` is set (and the metrics meaningless)
/// when the method failed on it.
struct EvaluationRow {
  std::string material;
  std::string method;
  std::size_t samples = 0;
  Metrics metrics;
  double milliseconds = 0.0;  ///< the reconstruction only, not the simulated capture
  std::string error;
};

/// \brief One method over every material it succeeded on: means of per-material values
/// (docs/method.md §6.1) and the worst materials by dE, worst first.
struct MethodSummary {
  std::string method;
  std::size_t materials = 0;
  std::size_t failures = 0;
  Metrics mean;
  double meanMilliseconds = 0.0;
  std::vector<EvaluationRow> worst;
};

/// \brief Summaries in `methods` order (methods without rows get an empty summary).
std::vector<MethodSummary> summarise(const std::vector<EvaluationRow>& rows,
                                     const std::vector<std::string>& methods,
                                     std::size_t worstCount = 5);

/// \brief The CSV header `material,method,samples,delta_e,rmse,psnr_db,relative_rmse,
/// peak_ratio,milliseconds,error` and one row; fields with a comma or quote are quoted.
void writeReportCsvHeader(std::ostream& out);
void writeReportCsvRow(std::ostream& out, const EvaluationRow& row);

/// \brief {"materials": [rows...], "means": [summaries...]}, numbers as JSON numbers.
nlohmann::json reportJson(const std::vector<EvaluationRow>& rows,
                          const std::vector<MethodSummary>& summaries);

}  // namespace slicecap::eval
