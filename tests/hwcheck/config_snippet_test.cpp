// The measured configuration: the guard it implies and its atomic, non-clobbering write.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "../support/test_support.hpp"
#include "slicecap/hwcheck/hardware_check.hpp"
#include "slicecap/hwcheck/hardware_check_error.hpp"
#include "slicecap/hwcheck/response_check.hpp"

namespace slicecap::hwcheck {
namespace {

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ConfigSnippet, GuardCoversTheOffsetAndSpreadButNeverBelowTheDefault) {
  EXPECT_DOUBLE_EQ(guardFor(40.0, 5.0), 200.0);
  EXPECT_DOUBLE_EQ(guardFor(-400.0, 20.0), 510.0);  // 400 + 60 + 50, rounded up to 10 us
}

TEST(ConfigSnippet, WritesOnceAndReplacesOnlyWhenAsked) {
  const auto dir = test::freshTempDir();
  const auto path = (dir / "measured.conf").string();
  writeConfigFile(path, "readout_us = 28800\n", false);
  EXPECT_EQ(slurp(path), "readout_us = 28800\n");
  try {
    writeConfigFile(path, "readout_us = 1\n", false);
    FAIL() << "an existing file was replaced";
  } catch (const hwcheck::HardwareCheckError& error) {
    EXPECT_NE(std::string(error.what()).find("measured.conf exists"), std::string::npos) << error.what();
  }
  EXPECT_EQ(slurp(path), "readout_us = 28800\n");
  writeConfigFile(path, "readout_us = 2\n", true);
  EXPECT_EQ(slurp(path), "readout_us = 2\n");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u) << "no temporary file left behind";
  EXPECT_THROW(writeConfigFile((dir / "missing" / "x.conf").string(), "", false), hwcheck::HardwareCheckError);
}

TEST(ConfigSnippet, ReportSnippetParsesAsKeyValueLines) {
  HardwareReport report;
  report.cameraId = "cam";
  report.configLines = {{"readout_us", "28801"}, {"led_guard_us", "200"}};
  EXPECT_EQ(report.configSnippet(),
            "# Measured by slicecapd --check-hardware on cam\nreadout_us = 28801\nled_guard_us = 200\n");
  EXPECT_EQ(report.json()["config"]["readout_us"], "28801");
}

TEST(CurveDistance, IsZeroForACurveAndItselfAndLargeForSrgbAgainstLinear) {
  EXPECT_DOUBLE_EQ(curveDistance(ToneCurve::srgb(), ToneCurve::srgb(), 5, 250, 250), 0.0);
  // sRGB decoded as linear: code 64's ratio to white is 0.25 against 0.051 (x 4.9).
  EXPECT_GT(curveDistance(ToneCurve::linear(), ToneCurve::srgb(), 64, 250, 250), 2.0);
}

}  // namespace
}  // namespace slicecap::hwcheck
