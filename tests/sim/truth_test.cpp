// truth.json: written and read back, and every kind of damage reported with the file and the field.
#include "slicecap/sim/truth.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace {

using namespace slicecap;
using namespace slicecap::sim;

SweepTruth twoFrameTruth() {
  SweepTruth truth;
  truth.material = "lambert:albedo=0.5";
  truth.materialDescription = "Lambert, albedo 0.5";
  truth.slice = {{SliceKind::Axial, {30, 75}}, 15.0};
  truth.ledIntensityWPerSr = 1.5;
  truth.sensorResponse = 2.0e-4;
  truth.ambientIrradiance = 0.3;
  for (int i = 0; i < 2; ++i) {
    FrameTruth frame;
    frame.file = "frame_" + std::to_string(i) + ".png";
    frame.timestampUs = 1000 * i;
    frame.ledOn = i == 0;
    frame.exposureUs = 8000.0;
    frame.pose.translationMm = {1.0, 2.0, 300.0 + i};
    frame.view = {75.0, 15.0 * i};
    frame.light = {30.0, 0.0};
    frame.brdf = {0.1, 0.2, 0.3};
    frame.markersInView = {0, 1, 2};
    truth.frames.push_back(frame);
  }
  return truth;
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// Reads `dir` and returns the error message; fails the test when reading succeeds.
std::string readError(const std::filesystem::path& dir) {
  try {
    readTruth(dir);
  } catch (const io::IoError& e) {
    return e.what();
  }
  ADD_FAILURE() << "a damaged truth file was read without an error";
  return {};
}

TEST(Truth, ReadsBackWhatWasWritten) {
  const auto dir = test::freshTempDir();
  const SweepTruth written = twoFrameTruth();
  writeTruth(dir, written);
  const SweepTruth read = readTruth(dir);
  EXPECT_EQ(read.material, written.material);
  EXPECT_EQ(read.slice, written.slice);
  ASSERT_EQ(read.frames.size(), 2u);
  EXPECT_EQ(read.frames[1].file, "frame_1.png");
  EXPECT_FALSE(read.frames[1].ledOn);
  EXPECT_DOUBLE_EQ(read.frames[1].pose.translationMm.z(), 301.0);
  EXPECT_DOUBLE_EQ(read.frames[1].view.phiDeg, 15.0);
  EXPECT_DOUBLE_EQ(read.frames[0].brdf[2], 0.3);
  EXPECT_EQ(read.frames[0].markersInView, (std::vector<int>{0, 1, 2}));
}

TEST(Truth, AMissingFileIsNamed) {
  const auto dir = test::freshTempDir();
  const std::string message = readError(dir);
  EXPECT_NE(message.find("truth.json"), std::string::npos) << message;
}

TEST(Truth, TruncatedJsonIsNamed) {
  const auto dir = test::freshTempDir();
  writeTruth(dir, twoFrameTruth());
  const std::string text = readText(dir / kTruthFile);
  writeText(dir / kTruthFile, text.substr(0, text.size() / 2));
  const std::string message = readError(dir);
  EXPECT_NE(message.find("truth.json"), std::string::npos) << message;
}

TEST(Truth, AMissingTopLevelFieldIsNamed) {
  const auto dir = test::freshTempDir();
  writeTruth(dir, twoFrameTruth());
  std::string text = readText(dir / kTruthFile);
  const auto at = text.find("\"sensor_response\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 17, "\"sensor_respons\"");
  writeText(dir / kTruthFile, text);
  const std::string message = readError(dir);
  EXPECT_NE(message.find("truth.json"), std::string::npos) << message;
  EXPECT_NE(message.find("sensor_response"), std::string::npos) << message;
}

TEST(Truth, ABadFieldInAFrameNamesTheFrame) {
  const auto dir = test::freshTempDir();
  writeTruth(dir, twoFrameTruth());
  std::string text = readText(dir / kTruthFile);
  // The second frame's led_on becomes a string.
  const auto first = text.find("\"led_on\"");
  const auto second = text.find("\"led_on\"", first + 1);
  ASSERT_NE(second, std::string::npos);
  const auto value = text.find("false", second);
  ASSERT_NE(value, std::string::npos);
  text.replace(value, 5, "\"no\"");
  writeText(dir / kTruthFile, text);
  const std::string message = readError(dir);
  EXPECT_NE(message.find("frames[1]"), std::string::npos) << message;
}

TEST(Truth, AnUnknownSliceKindIsNamed) {
  const auto dir = test::freshTempDir();
  writeTruth(dir, twoFrameTruth());
  std::string text = readText(dir / kTruthFile);
  const auto at = text.find("\"axial\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 7, "\"spiral\"");
  writeText(dir / kTruthFile, text);
  const std::string message = readError(dir);
  EXPECT_NE(message.find("slice.kind"), std::string::npos) << message;
}

// Whole-number fields: nlohmann's get<int>() of 1e300 is undefined behaviour and of 30.5 quietly
// 30, so each is checked and named.
std::string errorWithReplaced(const std::string& needle, const std::string& replacement) {
  const auto dir = test::freshTempDir();
  writeTruth(dir, twoFrameTruth());
  std::string text = readText(dir / kTruthFile);
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  if (at == std::string::npos) return {};
  text.replace(at, needle.size(), replacement);
  writeText(dir / kTruthFile, text);
  return readError(dir);
}

TEST(Truth, AnElevationThatIsNotAWholeNumberOfDegreesIsNamed) {
  for (const std::string bad : {"1e300", "30.5", "-30", "90"}) {
    const std::string message = errorWithReplaced("\"theta_i_deg\": 30", "\"theta_i_deg\": " + bad);
    EXPECT_NE(message.find("slice.theta_i_deg"), std::string::npos) << bad << ": " << message;
    EXPECT_NE(message.find("expected a whole number"), std::string::npos) << message;
  }
}

TEST(Truth, ATimestampThatIsNotAWholeNumberIsNamed) {
  const std::string message =
      errorWithReplaced("\"timestamp_us\": ", "\"timestamp_us\": 1e300,\"x\":");
  EXPECT_NE(message.find("frames[0]: timestamp_us"), std::string::npos) << message;
}

TEST(Truth, AMarkerIdThatIsNotAWholeNumberIsNamed) {
  for (const std::string bad : {"1e300", "2.5", "-1"}) {
    const std::string message =
        errorWithReplaced("\"markers_in_view\": [", "\"markers_in_view\": [" + bad + ",");
    EXPECT_NE(message.find("frames[0]: markers_in_view"), std::string::npos)
        << bad << ": " << message;
  }
}

}  // namespace
