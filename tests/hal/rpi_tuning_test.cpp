// slicecap's Raspberry Pi tuning file: which file the processed path runs with, the start-up
// check that refuses a file the IPA could not read, and what the shipped files hold.
#include "slicecap/hal/rpi_tuning.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "slicecap/hal/camera_error.hpp"

namespace slicecap::hal {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

TuningInputs piInputs(RawCapture raw, std::optional<bool> rawGranted) {
  TuningInputs inputs;
  inputs.raw = raw;
  inputs.rawGranted = rawGranted;
  inputs.sensorModel = "imx708";
  inputs.isp = PiIsp::Pisp;
  inputs.tuningDir = slicecapTuningDir();
  return inputs;
}

TEST(RpiTuning, TheSettingIsAutoOffOrAPath) {
  EXPECT_EQ(parseTuningFileSetting("auto")->kind, TuningFileSetting::Kind::Auto);
  EXPECT_EQ(parseTuningFileSetting("off")->kind, TuningFileSetting::Kind::Off);
  const auto path = parseTuningFileSetting("/etc/slicecap/mine.json");
  ASSERT_TRUE(path);
  EXPECT_EQ(path->kind, TuningFileSetting::Kind::Path);
  EXPECT_EQ(path->path, fs::path("/etc/slicecap/mine.json"));
  EXPECT_FALSE(parseTuningFileSetting(""));
}

TEST(RpiTuning, TheIspComesFromTheDeviceTreesSoc) {
  using namespace std::string_view_literals;
  EXPECT_EQ(piIspOfCompatible("raspberrypi,5-model-b\0brcm,bcm2712\0"sv), PiIsp::Pisp);
  EXPECT_EQ(piIspOfCompatible("raspberrypi,4-model-b\0brcm,bcm2711\0"sv), PiIsp::Vc4);
  EXPECT_EQ(piIspOfCompatible("raspberrypi,3-model-b\0brcm,bcm2837\0"sv), PiIsp::Vc4);
  EXPECT_FALSE(piIspOfCompatible("rockchip,rk3588\0"sv));
  EXPECT_FALSE(piIspOfCompatible(""sv));
}

TEST(RpiTuning, AutoSelectsSlicecapsFileForTheProcessedPathOnly) {
  const TuningFileSetting automatic{TuningFileSetting::Kind::Auto, {}};
  const TuningChoice off = chooseTuningFile(automatic, piInputs(RawCapture::Off, std::nullopt));
  ASSERT_TRUE(off.file) << off.reason;
  EXPECT_EQ(off.file->filename(), "slicecap-imx708-pisp.json");
  const TuningChoice noRaw = chooseTuningFile(automatic, piInputs(RawCapture::Auto, false));
  ASSERT_TRUE(noRaw.file) << noRaw.reason;

  // RAW bypasses the ISP: the camera's own tuning (its black level, its focus) stays.
  const TuningChoice raw = chooseTuningFile(automatic, piInputs(RawCapture::Auto, true));
  EXPECT_FALSE(raw.file);
  EXPECT_THAT(raw.reason, HasSubstr("RAW"));
  EXPECT_FALSE(chooseTuningFile(automatic, piInputs(RawCapture::On, std::nullopt)).file);
  // Not probed under auto: RAW is what a Pi grants, so nothing is set.
  EXPECT_FALSE(chooseTuningFile(automatic, piInputs(RawCapture::Auto, std::nullopt)).file);
}

TEST(RpiTuning, AutoTakesTheFileOfTheBoardsIsp) {
  TuningInputs inputs = piInputs(RawCapture::Off, std::nullopt);
  inputs.isp = PiIsp::Vc4;
  const TuningChoice vc4 = chooseTuningFile({TuningFileSetting::Kind::Auto, {}}, inputs);
  ASSERT_TRUE(vc4.file) << vc4.reason;
  EXPECT_EQ(vc4.file->filename(), "slicecap-imx708-vc4.json");
}

TEST(RpiTuning, AutoLeavesOtherSensorsAndBoardsTheirOwnTuningAndSaysWhy) {
  TuningInputs other = piInputs(RawCapture::Off, std::nullopt);
  other.sensorModel = "imx219";
  const TuningChoice imx219 = chooseTuningFile({TuningFileSetting::Kind::Auto, {}}, other);
  EXPECT_FALSE(imx219.file);
  EXPECT_THAT(imx219.reason, AllOf(HasSubstr("imx219"), HasSubstr("residual")));
  TuningInputs notPi = piInputs(RawCapture::Off, std::nullopt);
  notPi.isp.reset();
  EXPECT_FALSE(chooseTuningFile({TuningFileSetting::Kind::Auto, {}}, notPi).file);
}

TEST(RpiTuning, OffAndAPathAreTakenAsSaid) {
  EXPECT_FALSE(chooseTuningFile({TuningFileSetting::Kind::Off, {}},
                                piInputs(RawCapture::Off, std::nullopt))
                   .file);
  const TuningChoice path = chooseTuningFile({TuningFileSetting::Kind::Path, "/x/mine.json"},
                                             piInputs(RawCapture::Off, std::nullopt));
  ASSERT_TRUE(path.file);
  EXPECT_EQ(*path.file, fs::path("/x/mine.json"));
}

class BadTuningFile : public ::testing::Test {
 protected:
  fs::path dir_ = fs::path(::testing::TempDir()) / "slicecap-rpi-tuning-test";
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path file = dir_ / name;
    std::ofstream(file) << text;
    return file;
  }
};

TEST_F(BadTuningFile, AMissingFileIsRefusedNamingIt) {
  const fs::path missing = dir_ / "missing.json";
  EXPECT_THAT([&] { validateTuningFile(missing, std::nullopt); },
              ::testing::ThrowsMessage<CameraError>(
                  AllOf(HasSubstr(missing.string()), HasSubstr("cannot be read"))));
}

TEST_F(BadTuningFile, TextThatIsNotJsonIsRefusedNamingIt) {
  const fs::path file = write("broken.json", "{\"version\": 2.0, \"target\": \"pisp\",");
  EXPECT_THAT([&] { validateTuningFile(file, std::nullopt); },
              ::testing::ThrowsMessage<CameraError>(
                  AllOf(HasSubstr(file.string()), HasSubstr("not valid JSON"))));
}

TEST_F(BadTuningFile, AFileForTheOtherIspOrWithoutAlgorithmsIsRefused) {
  const fs::path vc4 =
      write("vc4.json", R"({"version": 2.0, "target": "bcm2835", "algorithms": [{"rpi.agc": {}}]})");
  EXPECT_NO_THROW(validateTuningFile(vc4, PiIsp::Vc4));
  EXPECT_THAT([&] { validateTuningFile(vc4, PiIsp::Pisp); },
              ::testing::ThrowsMessage<CameraError>(
                  AllOf(HasSubstr(vc4.string()), HasSubstr("\"pisp\""))));
  const fs::path empty = write("empty.json", R"({"version": 2.0, "target": "pisp"})");
  EXPECT_THAT([&] { validateTuningFile(empty, std::nullopt); },
              ::testing::ThrowsMessage<CameraError>(HasSubstr("algorithms")));
  const fs::path old = write("old.json", R"({"rpi.agc": {}})");
  EXPECT_THAT([&] { validateTuningFile(old, std::nullopt); },
              ::testing::ThrowsMessage<CameraError>(HasSubstr("version")));
}

// The shipped files hold what docs/real-sensors.md says of them: each ISP behaviour that changes
// with the image is off, and the IPA would accept each on its own ISP.
TEST(RpiTuning, TheShippedFilesTurnTheAdaptiveProcessingOff) {
  for (const auto& [name, isp] : {std::pair{"slicecap-imx708-vc4.json", PiIsp::Vc4},
                                  std::pair{"slicecap-imx708-pisp.json", PiIsp::Pisp}}) {
    const fs::path file = slicecapTuningDir() / name;
    SCOPED_TRACE(file.string());
    ASSERT_NO_THROW(validateTuningFile(file, isp));
    std::ifstream in(file);
    const nlohmann::json root = nlohmann::json::parse(in);
    std::map<std::string, nlohmann::json> algorithms;
    for (const nlohmann::json& entry : root.at("algorithms"))
      for (const auto& [key, value] : entry.items()) algorithms[key] = value;
    EXPECT_EQ(algorithms.at("rpi.contrast").at("ce_enable"), 0);
    EXPECT_EQ(algorithms.at("rpi.alsc").at("n_iter"), 0);
    EXPECT_FALSE(algorithms.at("rpi.alsc").contains("calibrations_Cr"));
    for (const nlohmann::json& ccm : algorithms.at("rpi.ccm").at("ccms"))
      EXPECT_EQ(ccm.at("ccm"), nlohmann::json({1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}));
    EXPECT_FALSE(algorithms.contains("rpi.tdn"));
    if (algorithms.contains("rpi.denoise")) {
      for (const auto& [mode, settings] : algorithms.at("rpi.denoise").items())
        EXPECT_FALSE(settings.contains("tdn")) << mode;
    }
  }
}

}  // namespace
}  // namespace slicecap::hal
