// End-to-end: the committed interpolation vectors (read by the Python tests) still match the C++
// code.
#include "grid_interpolation_vectors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

#include "slicecap/core/core_error.hpp"

namespace slicecap::vectors {
namespace {

const char* const kRegenerate =
    "; regenerate with build/tests/make_grid_interpolation_vectors "
    "tests/vectors/grid_interpolation.json";

nlohmann::json committed() {
  std::ifstream file(SLICECAP_GRID_VECTORS_FILE);
  if (!file) throw std::runtime_error(std::string(SLICECAP_GRID_VECTORS_FILE) + ": cannot open");
  return nlohmann::json::parse(file);
}

Direction directionOf(const nlohmann::json& pair) {
  return {pair.at(0).get<double>(), pair.at(1).get<double>()};
}

TEST(GridInterpolationVectors, CommittedValuesMatchEvaluate) {
  const nlohmann::json file = committed();
  const Abrdf table = hashTable();
  ASSERT_EQ(file.at("cases").size(), cases().size()) << kRegenerate;
  for (const nlohmann::json& c : file.at("cases")) {
    const Rgb value = evaluate(table, directionOf(c.at("light")), directionOf(c.at("view")));
    for (int channel = 0; channel < 3; ++channel) {
      const double expected = c.at("rgb").at(channel).get<double>();
      EXPECT_NEAR(value[channel], expected, 1e-12 * std::abs(expected)) << c.dump() << kRegenerate;
    }
  }
}

TEST(GridInterpolationVectors, CommittedFileIsWhatTheGeneratorWrites) {
  const nlohmann::json file = committed();
  const nlohmann::json fresh = build();
  EXPECT_EQ(file.at("table"), fresh.at("table")) << kRegenerate;
  EXPECT_EQ(file.at("invalid"), fresh.at("invalid")) << kRegenerate;
  ASSERT_EQ(file.at("cases").size(), fresh.at("cases").size()) << kRegenerate;
  for (std::size_t i = 0; i < fresh.at("cases").size(); ++i) {
    const nlohmann::json& a = file.at("cases").at(i);
    const nlohmann::json& b = fresh.at("cases").at(i);
    EXPECT_EQ(a.at("kind"), b.at("kind")) << i << kRegenerate;
    for (const char* side : {"light", "view"}) {
      for (int k = 0; k < 2; ++k) {
        EXPECT_DOUBLE_EQ(a.at(side).at(k).get<double>(), b.at(side).at(k).get<double>())
            << i << kRegenerate;
      }
    }
  }
}

TEST(GridInterpolationVectors, InvalidCasesAreRejected) {
  const Abrdf table = hashTable();
  for (const Case& c : invalidCases())
    EXPECT_THROW(evaluate(table, c.light, c.view), slicecap::CoreError) << c.kind;
}

TEST(GridInterpolationVectors, CoverEveryKindOfCase) {
  std::set<std::string> kinds;
  for (const Case& c : cases())
    kinds.insert(c.kind);
  EXPECT_EQ(kinds, (std::set<std::string>{"grid", "azimuth", "elevation", "pole", "wrap", "clamp",
                                          "random"}));
}

}  // namespace
}  // namespace slicecap::vectors
