// slicecapd.conf: the documented defaults parse to the defaults; every mistake names its line and
// key.
#include "slicecap/daemon/config.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace slicecap::daemon {
namespace {

DaemonConfig parse(const std::string& text) {
  std::istringstream in(text);
  return parseDaemonConfig(in, "slicecapd.conf");
}

std::string error(const std::string& text) {
  try {
    parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(DaemonConfig, TheDocumentedDefaultsAreTheDefaults) {
  const DaemonConfig fromFile = parse(DaemonConfig::documentedDefaults());
  const DaemonConfig defaults;
  EXPECT_EQ(fromFile.camera, defaults.camera);
  EXPECT_EQ(fromFile.widthPx, defaults.widthPx);
  EXPECT_EQ(fromFile.heightPx, defaults.heightPx);
  EXPECT_EQ(fromFile.ledLine, defaults.ledLine);
  EXPECT_EQ(fromFile.ledAlternate, defaults.ledAlternate);
  EXPECT_EQ(fromFile.storage, defaults.storage);
  EXPECT_EQ(fromFile.socket, defaults.socket);
  EXPECT_EQ(fromFile.socketGroup, defaults.socketGroup);
  EXPECT_EQ(fromFile.clientIdleTimeoutS, defaults.clientIdleTimeoutS);
  EXPECT_EQ(fromFile.clientIdleTimeoutS, 300);
  EXPECT_FALSE(fromFile.exposureUs.has_value());
  EXPECT_EQ(fromFile.cameraRaw, defaults.cameraRaw);
  EXPECT_EQ(fromFile.tuningFile.kind, hal::TuningFileSetting::Kind::Auto);
  EXPECT_EQ(fromFile.cameraRaw, hal::RawCapture::Auto);
  EXPECT_EQ(fromFile.modelRaw, "") << "the model offers no RAW stream unless asked";
  EXPECT_EQ(fromFile.textureResolution, 0) << "no texture unless asked";
  EXPECT_EQ(fromFile.sensorReadNoise, defaults.sensorReadNoise);
  EXPECT_EQ(fromFile.sensorFullWellElectrons, defaults.sensorFullWellElectrons);
  EXPECT_EQ(fromFile.textureFramesPerBin, defaults.textureFramesPerBin);
  EXPECT_EQ(fromFile.hdrLevels, 1) << "one exposure unless asked";
  EXPECT_EQ(fromFile.mainsHz, 0) << "the frame duration is the camera's unless asked";
  EXPECT_EQ(fromFile.modelRoomLight, defaults.modelRoomLight);
  EXPECT_EQ(fromFile.modelFlickerHz, defaults.modelFlickerHz);
  EXPECT_EQ(fromFile.modelFlickerDepth, defaults.modelFlickerDepth);
  EXPECT_EQ(parse("").storage, defaults.storage) << "an empty file is the defaults";
}

TEST(DaemonConfig, ReadsEveryKind) {
  const DaemonConfig c = parse(
      "camera = file  # plays a simulated session\n"
      "camera_recording = /srv/sim/felt\n"
      "camera_recording_speed = 4\n"
      "resolution = 1920x1080\n"
      "exposure_us = 8000\n"
      "led_active_low = yes\n"
      "led_line = 23\n"
      "storage = /tmp/slicecap\n"
      "texture_resolution = 128\n"
      "texture_frames_per_bin = 3\n"
      "client_idle_timeout_s = 0\n"
      "camera_raw = off\n"
      "model_raw = SBGGR12_CSI2P\n"
      "sensor_read_noise = 0.0038\n"
      "sensor_full_well_electrons = 4200\n"
      "hdr_levels = 3\n");
  EXPECT_EQ(c.hdrLevels, 3);
  EXPECT_EQ(c.sensorReadNoise, 0.0038);
  EXPECT_EQ(c.sensorFullWellElectrons, 4200.0);
  EXPECT_EQ(c.camera, DaemonConfig::CameraKind::File);
  EXPECT_EQ(c.cameraRaw, hal::RawCapture::Off);
  EXPECT_EQ(c.modelRaw, "SBGGR12_CSI2P");
  EXPECT_EQ(c.recording, "/srv/sim/felt");
  EXPECT_EQ(c.recordingSpeed, 4.0);
  EXPECT_EQ(c.widthPx, 1920);
  EXPECT_EQ(c.exposureUs, 8000.0);
  EXPECT_TRUE(c.ledActiveLow);
  EXPECT_EQ(c.ledLine, "23");
  EXPECT_EQ(c.textureResolution, 128);
  EXPECT_EQ(c.textureFramesPerBin, 3);
  EXPECT_EQ(c.clientIdleTimeoutS, 0) << "0: idle clients are never closed";
  EXPECT_NE(error("client_idle_timeout_s = -1\n").find("client_idle_timeout_s"), std::string::npos);
}

TEST(DaemonConfig, WarnsOfAV4l2CameraLeftOnAutoGain) {
  const auto warnings = [](const std::string& text) { return configWarnings(parse(text)); };
  const std::vector<std::string> autoGain = warnings("camera = v4l2\nexposure_us = 8000\n");
  ASSERT_EQ(autoGain.size(), 1u);
  EXPECT_NE(autoGain[0].find("auto gain runs"), std::string::npos);
  EXPECT_TRUE(warnings("camera = v4l2\nexposure_us = 8000\ngain = 2\n").empty());
  // Both empty, or only gain set: metered and locked at each sweep start.
  EXPECT_TRUE(warnings("camera = v4l2\n").empty());
  EXPECT_TRUE(warnings("camera = v4l2\ngain = 2\n").empty());
  // libcamera reports every frame's exposure and gain, which the pipeline divides out.
  EXPECT_TRUE(warnings("camera = libcamera\n").empty());
  EXPECT_TRUE(warnings("camera = file\ncamera_recording = /srv/sim\n").empty());
  // HDR on V4L2: its frames do not say the exposure they were taken at.
  const std::vector<std::string> hdr = warnings("camera = v4l2\nhdr_levels = 2\n");
  ASSERT_EQ(hdr.size(), 1u);
  EXPECT_NE(hdr[0].find("do not report the exposure"), std::string::npos);
  EXPECT_TRUE(warnings("camera = libcamera\nhdr_levels = 2\n").empty());
}

TEST(DaemonConfig, NamesTheLineAndKeyOfEveryMistake) {
  EXPECT_EQ(error("camera = webcam\n"),
            "slicecapd.conf:1: camera: 'webcam' is not libcamera, v4l2, file or model");
  EXPECT_EQ(error("\n\nresoluton = 640x480\n"), "slicecapd.conf:3: unknown key 'resoluton'");
  EXPECT_EQ(error("resolution = 640\n"), "slicecapd.conf:1: resolution: '640' is not WIDTHxHEIGHT");
  EXPECT_NE(error("resolution = 99999x10\n").find("between 64 and 8192"), std::string::npos);
  EXPECT_EQ(error("gain = -2\n"), "slicecapd.conf:1: gain: '-2' is not a positive gain");
  EXPECT_EQ(error("camera_recording_speed = 0\n"),
            "slicecapd.conf:1: camera_recording_speed: '0' is not a speed from 0.01 to 1000 (1: as recorded)");
  // A speed whose period overflows the clock's microseconds is refused, not undefined.
  EXPECT_EQ(error("camera_recording_speed = 1e-300\n"),
            "slicecapd.conf:1: camera_recording_speed: '1e-300' is not a speed from 0.01 to 1000 (1: as recorded)");
  EXPECT_EQ(error("led_alternate = maybe\n"),
            "slicecapd.conf:1: led_alternate: 'maybe' is not true or false");
  EXPECT_EQ(error("storage = /a\nstorage = /b\n"), "slicecapd.conf:2: storage: set twice");
  EXPECT_EQ(error("just words\n"), "slicecapd.conf:1: expected 'key = value', got 'just words'");
  EXPECT_NE(error("camera = file\n").find("needs camera_recording"), std::string::npos);
  EXPECT_NE(error("storage = relative/dir\n").find("absolute"), std::string::npos);
  EXPECT_EQ(error("texture_resolution = 128.5\n"),
            "slicecapd.conf:1: texture_resolution: '128.5' is not a whole number in 0..512 "
            "(texels across the window (0: off))");
  EXPECT_NE(error("texture_frames_per_bin = 0\n").find("1..64"), std::string::npos);
  EXPECT_EQ(error("camera_raw = yes\n"), "slicecapd.conf:1: camera_raw: 'yes' is not auto, on or off");
  EXPECT_NE(error("model_raw = RGGB_PISP_COMP1\n").find("not a RAW format slicecap decodes"),
            std::string::npos);
  EXPECT_EQ(error("sensor_read_noise = 0.7\n"),
            "slicecapd.conf:1: sensor_read_noise: '0.7' is not a read noise in 0..0.5 of full scale");
  EXPECT_NE(error("sensor_full_well_electrons = 0\n").find("positive"), std::string::npos);
  EXPECT_EQ(error("hdr_levels = 4\n"),
            "slicecapd.conf:1: hdr_levels: '4' is not a whole number in 1..3 (exposures an HDR "
            "sweep alternates (1: no HDR))");
  EXPECT_NE(error("hdr_levels = 2\nled_alternate = false\n").find("needs led_alternate = true"),
            std::string::npos);
  EXPECT_EQ(error("hdr_levels = 1\nled_alternate = false\n"), "");
  EXPECT_THROW(readDaemonConfig("/nonexistent/slicecapd.conf"), ConfigError);
}

TEST(DaemonConfig, ReadsTheMainsFrequencyAndTheModelsRoomLight) {
  const DaemonConfig c = parse(
      "mains_hz = 60\n"
      "model_room_light = 0.15\n"
      "model_flicker_hz = 120\n"
      "model_flicker_depth = 0.3\n");
  EXPECT_EQ(c.mainsHz, 60);
  EXPECT_EQ(c.modelRoomLight, 0.15);
  EXPECT_EQ(c.modelFlickerHz, 120.0);
  EXPECT_EQ(c.modelFlickerDepth, 0.3);
  EXPECT_EQ(parse("mains_hz = 50\n").mainsHz, 50);
  EXPECT_EQ(parse("mains_hz = 0\n").mainsHz, 0);
  EXPECT_EQ(parse("model_flicker_hz = 0\n").modelFlickerHz, 0.0) << "0: steady room light";
}

TEST(DaemonConfig, RoomLightUnseenIsOffUnlessADistanceIsGiven) {
  EXPECT_EQ(parse("").roomLightUnseenMm, 0.0);
  EXPECT_EQ(parse("room_light_unseen_mm = 15\n").roomLightUnseenMm, 15.0);
  for (const std::string bad : {"-1", "", "far", "15mm", "2000"})
    EXPECT_EQ(error("room_light_unseen_mm = " + bad + "\n"),
              "slicecapd.conf:1: room_light_unseen_mm: '" + bad +
                  "' is not a distance in mm from 0 (off) to 1000")
        << bad;
}

TEST(DaemonConfig, RefusesAMainsFrequencyOtherThan50Or60Or0NamingLineKeyAndValue) {
  // Any other value would pin frames to a flicker the room does not have: never a silent default.
  for (const std::string bad : {"55", "50.0", "100", "", "fifty", "-50", "120"}) {
    const std::string message = error("\nmains_hz = " + bad + "\n");
    EXPECT_EQ(message, "slicecapd.conf:2: mains_hz: '" + bad +
                           "' is not 50, 60 or 0 (the mains frequency of the room's lights in "
                           "Hz; 0: do not pin the frame duration)")
        << bad;
  }
  EXPECT_EQ(error("model_flicker_depth = 1.5\n"),
            "slicecapd.conf:1: model_flicker_depth: '1.5' is not a flicker depth in 0..1");
  EXPECT_EQ(error("model_flicker_hz = 0.5\n"),
            "slicecapd.conf:1: model_flicker_hz: '0.5' is not a frequency in Hz, 0 or 1..1000");
  EXPECT_EQ(error("model_room_light = -0.1\n"),
            "slicecapd.conf:1: model_room_light: '-0.1' is not a fraction of the LED's "
            "irradiance in 0..10");
}

TEST(DaemonConfig, ReadsTheTuningFileAsAutoOffOrAPathAndRefusesNothing) {
  EXPECT_EQ(parse("tuning_file = off\n").tuningFile.kind, hal::TuningFileSetting::Kind::Off);
  const DaemonConfig path = parse("tuning_file = /etc/slicecap/imx708.json\n");
  EXPECT_EQ(path.tuningFile.kind, hal::TuningFileSetting::Kind::Path);
  EXPECT_EQ(path.tuningFile.path, std::filesystem::path("/etc/slicecap/imx708.json"));
  EXPECT_EQ(error("tuning_file =\n"),
            "slicecapd.conf:1: tuning_file: '' is not auto, off or a tuning file's path");
}

TEST(DaemonConfig, ReadsTheModelsPiAndIspAndRefusesAnythingElseNamingLineKeyAndValue) {
  const DaemonConfig c = parse(
      "model_pipeline = vc4\n"
      "model_adaptive_contrast = false\n"
      "model_colour_matrix = imx708\n"
      "model_stream = rec709\n"
      "model_temporal_denoise = 0\n"
      "model_timestamp_jitter_us = 0\n"
      "model_lock_counting = truth\n");
  EXPECT_EQ(c.modelPipeline, "vc4");
  EXPECT_FALSE(c.modelAdaptiveContrast);
  EXPECT_EQ(c.modelColourMatrix, "imx708");
  EXPECT_EQ(c.modelStream, "rec709");
  EXPECT_EQ(c.modelTemporalDenoise, 0.0);
  EXPECT_EQ(c.modelTimestampJitterUs, 0.0);
  EXPECT_FALSE(c.modelLocksCountedByRequest);
  const DaemonConfig defaults = parse("");
  EXPECT_EQ(defaults.modelPipeline, "pisp");
  EXPECT_TRUE(defaults.modelAdaptiveContrast);
  EXPECT_TRUE(defaults.modelLocksCountedByRequest);
  EXPECT_EQ(error("model_pipeline = pi5\n"),
            "slicecapd.conf:1: model_pipeline: 'pi5' is not vc4 or pisp");
  EXPECT_EQ(error("model_stream = yuv\n"),
            "slicecapd.conf:1: model_stream: 'yuv' is not rgb, rec709 or sycc");
  EXPECT_EQ(error("model_colour_matrix = srgb\n"),
            "slicecapd.conf:1: model_colour_matrix: 'srgb' is not imx708 or identity");
  EXPECT_EQ(error("model_temporal_denoise = 1\n"),
            "slicecapd.conf:1: model_temporal_denoise: '1' is not a weight of the previous frame "
            "in 0..0.95");
  EXPECT_EQ(error("model_lock_counting = sensor\n"),
            "slicecapd.conf:1: model_lock_counting: 'sensor' is not request or truth");
}

}  // namespace
}  // namespace slicecap::daemon
