// Means, worst cases, and the CSV/JSON forms of an evaluation.
#include "slicecap/eval/report.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace slicecap::eval {
namespace {

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text)
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return quoted + "\"";
}

nlohmann::json metricsJson(const Metrics& m) {
  return {{"delta_e", m.deltaE},
          {"rmse", m.rmse},
          {"psnr_db", m.psnrDb},
          {"relative_rmse", m.relativeRmse},
          {"peak_ratio", m.peakRatio}};
}

nlohmann::json rowJson(const EvaluationRow& row) {
  nlohmann::json j{{"material", row.material},
                   {"method", row.method},
                   {"samples", row.samples},
                   {"milliseconds", row.milliseconds}};
  if (row.error.empty()) {
    j.update(metricsJson(row.metrics));
  } else {
    j["error"] = row.error;
  }
  return j;
}

}  // namespace

std::vector<MethodSummary> summarise(const std::vector<EvaluationRow>& rows,
                                     const std::vector<std::string>& methods,
                                     std::size_t worstCount) {
  std::vector<MethodSummary> summaries;
  for (const std::string& method : methods) {
    MethodSummary s{method, 0, 0, {}, 0.0, {}};
    s.mean.peakRatio = 0.0;  // a sum until divided
    for (const EvaluationRow& row : rows) {
      if (row.method != method) continue;
      if (!row.error.empty()) {
        ++s.failures;
        continue;
      }
      ++s.materials;
      s.mean.deltaE += row.metrics.deltaE;
      s.mean.rmse += row.metrics.rmse;
      s.mean.psnrDb += row.metrics.psnrDb;
      s.mean.relativeRmse += row.metrics.relativeRmse;
      s.mean.peakRatio += row.metrics.peakRatio;
      s.meanMilliseconds += row.milliseconds;
      s.worst.push_back(row);
    }
    if (s.materials > 0) {
      const double n = double(s.materials);
      s.mean = {s.mean.deltaE / n, s.mean.rmse / n, s.mean.psnrDb / n, s.mean.relativeRmse / n,
                s.mean.peakRatio / n};
      s.meanMilliseconds /= n;
    }
    std::stable_sort(s.worst.begin(), s.worst.end(), [](const auto& a, const auto& b) {
      return a.metrics.deltaE > b.metrics.deltaE;
    });
    if (s.worst.size() > worstCount) s.worst.resize(worstCount);
    summaries.push_back(std::move(s));
  }
  return summaries;
}

void writeReportCsvHeader(std::ostream& out) {
  out << "material,method,samples,delta_e,rmse,psnr_db,relative_rmse,peak_ratio,milliseconds,"
         "error\n";
}

void writeReportCsvRow(std::ostream& out, const EvaluationRow& row) {
  char numbers[256];
  if (row.error.empty()) {
    std::snprintf(numbers, sizeof numbers, "%zu,%.4f,%.4f,%.4f,%.6f,%.4f,%.3f", row.samples,
                  row.metrics.deltaE, row.metrics.rmse, row.metrics.psnrDb,
                  row.metrics.relativeRmse, row.metrics.peakRatio, row.milliseconds);
  } else {
    std::snprintf(numbers, sizeof numbers, "%zu,,,,,,%.3f", row.samples, row.milliseconds);
  }
  out << csvField(row.material) << "," << csvField(row.method) << "," << numbers << ","
      << csvField(row.error) << "\n";
}

nlohmann::json reportJson(const std::vector<EvaluationRow>& rows,
                          const std::vector<MethodSummary>& summaries) {
  nlohmann::json j{{"materials", nlohmann::json::array()}, {"means", nlohmann::json::array()}};
  for (const EvaluationRow& row : rows)
    j["materials"].push_back(rowJson(row));
  for (const MethodSummary& s : summaries) {
    nlohmann::json summary{{"method", s.method},
                           {"materials", s.materials},
                           {"failures", s.failures},
                           {"milliseconds", s.meanMilliseconds},
                           {"worst", nlohmann::json::array()}};
    summary.update(metricsJson(s.mean));
    for (const EvaluationRow& w : s.worst)
      summary["worst"].push_back({{"material", w.material}, {"delta_e", w.metrics.deltaE}});
    j["means"].push_back(summary);
  }
  return j;
}

}  // namespace slicecap::eval
