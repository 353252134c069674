// The material fit on every built-in analytic material (issue 30 goals): the fit of the true
// table, its recovered roughness and tangent against the truth where the truth is a GGX or Ward
// lobe, its dE/RMSE/PSNR, the model chosen, and the time. A program, not a Google Benchmark:
// docs/results/2026-12-02-material-fit.md quotes its output.
#include <ctime>
#include <cstdio>
#include <regex>
#include <string>

#include "slicecap/fit/material_fit.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace {

using namespace slicecap;

// The truth's lobe parameters, read back from describe() ("... ax=0.06 ay=0.35 tangent_deg=0"),
// canonicalised as the fit's (tangent = axis of the larger alpha, [0, 180)).
struct TrueLobe {
  bool present = false;
  double alphaTangent = 0.0, alphaBitangent = 0.0, tangentDeg = 0.0;
};

TrueLobe trueLobe(const std::string& description) {
  static const std::regex pattern(R"(ax=([0-9.]+) ay=([0-9.]+) tangent_deg=([0-9.]+))");
  std::smatch match;
  TrueLobe lobe;
  if (!std::regex_search(description, match, pattern)) return lobe;
  fit::FittedMaterial m;
  m.alphaTangent = std::stod(match[1]);
  m.alphaBitangent = std::stod(match[2]);
  m.tangentDeg = std::stod(match[3]);
  m = m.canonical();
  return {true, m.alphaTangent, m.alphaBitangent, m.tangentDeg};
}

}  // namespace

int main() {
  std::printf("%-20s %-10s %-6s %8s %8s %8s %8s %8s %8s %7s %6s %6s %7s\n", "material", "family",
              "model", "aT", "aT err%", "aB", "aB err%", "tan deg", "tan err", "dE", "RMSE",
              "PSNR", "cpu s");
  for (auto* list : {models::anisotropicMaterials, models::isotropicMaterials}) {
    for (const models::NamedMaterial& named : list()) {
      const std::string description = named.model->describe();
      const Abrdf table = models::tabulate(*named.model);
      // Processor time, not wall time: on a shared machine the wall clock measures the neighbours.
      const std::clock_t start = std::clock();
      const fit::FitResult result = fit::fitMaterial(table, named.name);
      const double seconds = double(std::clock() - start) / CLOCKS_PER_SEC;
      const fit::FittedMaterial& m = result.material;
      const TrueLobe truth = trueLobe(description);
      const std::string family = description.substr(0, description.find(' '));
      char errors[96] = "";
      if (truth.present) {
        const bool isotropic = truth.alphaTangent == truth.alphaBitangent;
        std::snprintf(errors, sizeof errors, "%8.2f %8.4f %8.2f %8.2f %8.2f",
                      100.0 * (m.alphaTangent / truth.alphaTangent - 1.0), m.alphaBitangent,
                      100.0 * (m.alphaBitangent / truth.alphaBitangent - 1.0), m.tangentDeg,
                      isotropic ? 0.0 : fit::tangentDifferenceDeg(m.tangentDeg, truth.tangentDeg));
      } else {
        std::snprintf(errors, sizeof errors, "%8s %8.4f %8s %8.2f %8s", "-", m.alphaBitangent, "-",
                      m.tangentDeg, "-");
      }
      std::printf("%-20s %-10s %-6s %8.4f %s %7.3f %6.2f %6.1f %7.3f\n", named.name.c_str(),
                  family.c_str(), std::string(toString(m.model)) == "ggx" ? "ggx" : "+sheen",
                  m.alphaTangent, errors, result.metrics.deltaE, result.metrics.rmse,
                  result.metrics.psnrDb, seconds);
      std::printf("    %s\n    choice: %s\n", description.c_str(), result.choiceReason.c_str());
    }
  }
  return 0;
}
