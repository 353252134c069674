// recording.json: what the writer appends reads back, and every bad field is named.
#include "slicecap/io/recording.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::io {
namespace {

Recording smallHeader(PixelEncoding encoding) {
  Recording r;
  r.createdBy = "recording_test";
  r.camera.intrinsics = {16, 12, 20.0, 21.0, 7.5, 5.5};
  r.camera.distortion = {-0.05, 0.01, 0.001, -0.001, 0.0};
  r.encoding = encoding;
  r.slice = RecordedSlice{{SliceKind::Axial, {30, 75}}, 15.0};
  r.target = vision::defaultTarget();
  return r;
}

Image gradient(int channels, int bitDepth, int offset) {
  Image image{16, 12, channels, bitDepth, std::vector<std::uint16_t>(16 * 12 * channels)};
  for (std::size_t i = 0; i < image.samples.size(); ++i)
    image.samples[i] =
        static_cast<std::uint16_t>((i * 37 + offset) % (bitDepth == 8 ? 256 : 65536));
  return image;
}

// Writes a two-frame recording, then lets `edit` change its manifest's JSON.
std::filesystem::path editedRecording(const std::function<void(nlohmann::json&)>& edit) {
  const auto dir = test::freshTempDir() / "rec";
  RecordingWriter writer(dir, smallHeader(PixelEncoding::Srgb8));
  writer.append(gradient(3, 8, 0), {"", 1000, true, 5000.0, 1.0});
  writer.append(gradient(3, 8, 1), {"", 34333, false, 5000.0, 1.0});
  nlohmann::json manifest = readJsonFile(dir / kRecordingManifest);
  edit(manifest);
  std::ofstream(dir / kRecordingManifest) << manifest.dump(1);
  return dir;
}

std::string readError(const std::filesystem::path& dir) {
  try {
    readRecording(dir);
  } catch (const IoError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Recording, WriterAppendsFramesThatReadBackExactly) {
  for (PixelEncoding encoding : {PixelEncoding::Srgb8, PixelEncoding::Linear16}) {
    const auto dir = test::freshTempDir() / std::string(toString(encoding));
    RecordingWriter writer(dir, smallHeader(encoding));
    const int bits = bitDepthOf(encoding);
    writer.append(gradient(3, bits, 0), {"", 0, true, 8000.0, 2.0});
    writer.append(gradient(1, bits, 5), {"", 33333, false, 8000.0, 2.0});
    const Recording read = readRecording(dir);
    EXPECT_EQ(read, writer.recording());
    EXPECT_EQ(read.frames[1].file, "frame-00001.png");
    EXPECT_EQ(read.camera.distortion.p1, 0.001);
  }
}

TEST(Recording, ALiveFramesLedExposureReadsBackExactly) {
  const auto dir = test::freshTempDir() / "rec";
  RecordingWriter writer(dir, smallHeader(PixelEncoding::Srgb8));
  RecordedFrame frame{"", 1000, true, 5000.0, 1.0};
  frame.ledExposure = RecordedLedExposure{-4000, 40.0, 5000.0, 200.0, false, {{-3000, true}, {2500, false}}};
  writer.append(gradient(3, 8, 0), frame);
  writer.append(gradient(3, 8, 1), {"", 34333, false, 5000.0, 1.0});
  const Recording read = readRecording(dir);
  ASSERT_EQ(read.frames.size(), 2u);
  ASSERT_TRUE(read.frames[0].ledExposure);
  EXPECT_EQ(*read.frames[0].ledExposure, *frame.ledExposure);
  EXPECT_FALSE(read.frames[1].ledExposure);
}

TEST(Recording, AnHdrFramesExposureLevelReadsBackAndIsAbsentOtherwise) {
  const auto dir = test::freshTempDir() / "rec";
  RecordingWriter writer(dir, smallHeader(PixelEncoding::Srgb8));
  RecordedFrame longFrame{"", 1000, true, 8000.0, 1.0};
  longFrame.exposureLevel = 0;
  RecordedFrame shortFrame{"", 2000, true, 400.0, 1.0};
  shortFrame.exposureLevel = 2;
  writer.append(gradient(3, 8, 0), longFrame);
  writer.append(gradient(3, 8, 1), shortFrame);
  writer.append(gradient(3, 8, 2), {"", 3000, false, 400.0, 1.0});
  const Recording read = readRecording(dir);
  EXPECT_EQ(read, writer.recording());
  EXPECT_EQ(read.frames[0].exposureLevel, 0);
  EXPECT_EQ(read.frames[1].exposureLevel, 2);
  EXPECT_FALSE(read.frames[2].exposureLevel);
  EXPECT_FALSE(readJsonFile(dir / kRecordingManifest)["frames"][2].contains("exposure_level"));
}

TEST(Recording, WriterRefusesToOverwriteARecordingAndRejectsBadFrames) {
  const auto dir = test::freshTempDir() / "rec";
  RecordingWriter writer(dir, smallHeader(PixelEncoding::Srgb8));
  EXPECT_THROW(RecordingWriter(dir, smallHeader(PixelEncoding::Srgb8)), IoError);
  EXPECT_THROW(writer.append(gradient(3, 16, 0), {"", 0, true, 1.0, 1.0}), io::IoError);
  writer.append(gradient(3, 8, 0), {"", 10, true, 1.0, 1.0});
  EXPECT_THROW(writer.append(gradient(3, 8, 0), {"", 10, true, 1.0, 1.0}), io::IoError);
  // What was captured before the bad frame is still there.
  EXPECT_EQ(readRecording(dir).frames.size(), 1u);
}

TEST(Recording, ReaderNamesTheFieldThatIsWrong) {
  struct Case {
    const char* field;
    std::function<void(nlohmann::json&)> edit;
  };
  const std::vector<Case> cases = {
      {"frames[1].exposure_us", [](auto& j) { j["frames"][1]["exposure_us"] = -5; }},
      {"frames[1].timestamp_us", [](auto& j) { j["frames"][1]["timestamp_us"] = 1000; }},
      {"frames[1].exposure_level", [](auto& j) { j["frames"][1]["exposure_level"] = 3; }},
      {"frames[0].exposure_level", [](auto& j) { j["frames"][0]["exposure_level"] = -1; }},
      {"frames[0].exposure_level", [](auto& j) { j["frames"][0]["exposure_level"] = "long"; }},
      {"frames[0].file", [](auto& j) { j["frames"][0]["file"] = "../elsewhere.png"; }},
      {"frames[1].file", [](auto& j) { j["frames"][1]["file"] = "missing.png"; }},
      {"frames[0].led_on", [](auto& j) { j["frames"][0]["led_on"] = "yes"; }},
      {"pixel_encoding", [](auto& j) { j["pixel_encoding"] = "raw10"; }},
      {"slice.kind", [](auto& j) { j["slice"]["kind"] = "sideways"; }},
      {"slice.kind", [](auto& j) { j["slice"]["kind"] = "point"; }},
      {"camera.fx_px", [](auto& j) { j["camera"]["fx_px"] = 0; }},
      // A size no frame could be allocated for (simulate --camera failed with bad_alloc).
      {"camera.width_px", [](auto& j) { j["camera"]["width_px"] = kMaxCameraSidePx + 1; }},
      {"format_version", [](auto& j) { j["format_version"] = 99; }},
      {"decoding", [](auto& j) { j["decoding"] = "gamma"; }},
      // These frames are 8-bit: a black above 0 is a linear16 recording's only.
      {"decoding_black16", [](auto& j) { j["decoding_black16"] = 4096; }},
      {"decoding_curve", [](auto& j) { j["decoding"] = "measured-curve"; }},
      {"decoding_curve.points",
       [](auto& j) {
         j["decoding"] = "measured-curve";
         j["decoding_curve"] = {{"name", "measured"}, {"points", {{0, 0}, {0.5, 0.2}, {0.4, 0.6}, {1, 1}}}};
       }},
      {"room_light_unseen_mm", [](auto& j) { j["room_light_unseen_mm"] = 0; }},
      {"room_light_unseen_mm", [](auto& j) { j["room_light_unseen_mm"] = "15 mm"; }},
      {"room_light_unseen_mm", [](auto& j) { j["room_light_unseen_mm"] = 1001; }},
      {"target", [](auto& j) { j.erase("target"); }},
      // Not tag 3 (the id was cast to int, which wrapped round).
      {"target.markers[0].id", [](auto& j) { j["target"]["markers"][0]["id"] = 4294967299; }},
      {"frames[1].led_exposure.exposure_us",
       [](auto& j) {
         j["frames"][1]["led_exposure"] = {{"row0_start_us", 0},    {"line_time_us", 40.0},
                                           {"exposure_us", 0.0},    {"guard_us", 200.0},
                                           {"on_at_start", false},  {"changes", nlohmann::json::array()}};
       }},
      {"frames[0].led_exposure.changes[1].time_us",
       [](auto& j) {
         j["frames"][0]["led_exposure"] = {
             {"row0_start_us", 0},   {"line_time_us", 40.0}, {"exposure_us", 100.0},
             {"guard_us", 200.0},    {"on_at_start", false},
             {"changes", {{{"time_us", 50}, {"on", true}}, {{"time_us", 20}, {"on", false}}}}};
       }},
  };
  for (const Case& c : cases) {
    const std::string message = readError(editedRecording(c.edit));
    EXPECT_NE(message.find(kRecordingManifest), std::string::npos) << message;
    EXPECT_NE(message.find(c.field), std::string::npos) << c.field << ": " << message;
  }
}

TEST(Recording, DecodingRoundTripsAndIsImpliedByTheEncodingWhenAbsent) {
  const auto dir = test::freshTempDir() / "rec";
  Recording header = smallHeader(PixelEncoding::Srgb8);
  header.decoding = RecordedDecoding{RecordedDecoding::Kind::MeasuredCurve,
                                     ToneCurve("measured", {{0, 0}, {0.2, 0.5}, {1, 1}})};
  RecordingWriter writer(dir, header);
  writer.append(gradient(3, 8, 0), {"", 0, true, 100.0, 1.0});
  const nlohmann::json manifest = readJsonFile(dir / kRecordingManifest);
  EXPECT_EQ(manifest["decoding"], "measured-curve");
  EXPECT_EQ(manifest["format_version"], 2);
  const Recording read = readRecording(dir);
  EXPECT_EQ(read, writer.recording());
  ASSERT_TRUE(read.decoding && read.decoding->toneCurve());
  EXPECT_DOUBLE_EQ(read.decoding->toneCurve()->decode(0.5), 0.2);
  // A version 1 recording says nothing: sRGB for 8-bit, linear for 16-bit.
  const auto old = editedRecording([](auto& j) { j["format_version"] = 1; });
  EXPECT_FALSE(readRecording(old).decoding);
  EXPECT_EQ(RecordedDecoding::defaultFor(PixelEncoding::Srgb8).kind, RecordedDecoding::Kind::Srgb);
  EXPECT_FALSE(RecordedDecoding::defaultFor(PixelEncoding::Srgb8).toneCurve());
  EXPECT_EQ(RecordedDecoding::defaultFor(PixelEncoding::Linear16).toneCurve()->name(), "linear");
}

TEST(Recording, ALinearRecordingsBlackRoundTripsAtVersionThree) {
  const auto dir = test::freshTempDir() / "rec";
  Recording header = smallHeader(PixelEncoding::Linear16);
  header.decoding = RecordedDecoding{RecordedDecoding::Kind::Linear, std::nullopt, 4096};
  RecordingWriter writer(dir, header);
  writer.append(gradient(3, 16, 0), {"", 0, true, 100.0, 1.0});
  const nlohmann::json manifest = readJsonFile(dir / kRecordingManifest);
  EXPECT_EQ(manifest["decoding_black16"], 4096);
  EXPECT_EQ(manifest["format_version"], 3);
  const Recording read = readRecording(dir);
  EXPECT_EQ(read, writer.recording());
  ASSERT_TRUE(read.decoding);
  EXPECT_EQ(read.decoding->black16, 4096);
  // Another black is another decoding; one past the top is refused, naming the field.
  EXPECT_FALSE((RecordedDecoding{RecordedDecoding::Kind::Linear, std::nullopt, 0} == *read.decoding));
  nlohmann::json edited = manifest;
  edited["decoding_black16"] = 65535;
  writeJsonFileAtomically(dir / kRecordingManifest, edited);
  EXPECT_NE(readError(dir).find("decoding_black16"), std::string::npos) << readError(dir);
}

// The capture's room-light gate (slicecapd's room_light_unseen_mm) travels with its frames; a
// recording without it (every one before it was recorded) reads as ungated.
TEST(Recording, TheRoomLightGateRoundTripsAndIsAbsentWhenOff) {
  const auto dir = test::freshTempDir() / "rec";
  Recording header = smallHeader(PixelEncoding::Srgb8);
  header.roomLightUnseenMm = 15.0;
  RecordingWriter writer(dir, header);
  writer.append(gradient(3, 8, 0), {"", 0, true, 100.0, 1.0});
  EXPECT_EQ(readJsonFile(dir / kRecordingManifest)["room_light_unseen_mm"], 15.0);
  EXPECT_EQ(readRecording(dir), writer.recording());
  const auto plain = test::freshTempDir() / "rec";
  RecordingWriter(plain, smallHeader(PixelEncoding::Srgb8));
  EXPECT_FALSE(readJsonFile(plain / kRecordingManifest).contains("room_light_unseen_mm"));
  EXPECT_FALSE(readRecording(plain).roomLightUnseenMm);
}

TEST(Recording, CameraMayComeFromACalibrationFileInsideTheRecording) {
  const auto dir = test::freshTempDir() / "rec";
  Recording header = smallHeader(PixelEncoding::Srgb8);
  header.calibrationFile = "camera.json";
  std::filesystem::create_directories(dir);
  writeJsonFileAtomically(dir / "camera.json", cameraToJson(header.camera));
  RecordingWriter writer(dir, header);
  writer.append(gradient(3, 8, 0), {"", 0, true, 100.0, 1.0});
  EXPECT_FALSE(readJsonFile(dir / kRecordingManifest)["camera"].contains("fx_px"));
  EXPECT_EQ(readRecording(dir), writer.recording());
  // A bad calibration is named by its own file and field.
  nlohmann::json camera = readJsonFile(dir / "camera.json");
  camera["fy_px"] = -1;
  std::ofstream(dir / "camera.json") << camera.dump();
  const std::string message = readError(dir);
  EXPECT_NE(message.find("camera.json"), std::string::npos) << message;
  EXPECT_NE(message.find("fy_px"), std::string::npos) << message;
}

// nlohmann reports a number beyond a double as out_of_range, not as a parse error: found by
// tests/fuzz/target_json_fuzz, it escaped the readers as a bare nlohmann exception.
TEST(Recording, ANumberBeyondADoubleIsInvalidJsonNamingTheFile) {
  const auto dir = test::freshTempDir();
  std::ofstream(dir / "target.json") << R"({"name": "t", "units": "mm", "family": 8e888})";
  try {
    readTargetJson(dir / "target.json");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("target.json: not valid JSON"), std::string::npos) << message;
    EXPECT_NE(message.find("8e888"), std::string::npos) << message;
  }
  const auto rec = editedRecording([](auto&) {});
  std::string manifest = readJsonFile(rec / kRecordingManifest).dump(1);
  manifest.replace(manifest.find("5000.0"), 6, "1e400");
  std::ofstream(rec / kRecordingManifest) << manifest;
  const std::string message = readError(rec);
  EXPECT_NE(message.find(kRecordingManifest + std::string(": not valid JSON")), std::string::npos)
      << message;
}

// nlohmann's parser does not recurse, but its dump does: the message naming a field of the wrong
// type printed a value nested 200000 deep and overflowed the stack (tests/fuzz/target_json_fuzz).
TEST(Recording, JsonNestedTooDeepIsRefusedNamingTheFile) {
  const auto dir = test::freshTempDir();
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  std::ofstream(dir / "target.json") << R"({"name": "t", "units": "mm", "family": )" << deep << "}";
  try {
    readTargetJson(dir / "target.json");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("target.json: not valid JSON (arrays and objects nested "
                                         "deeper than 64 levels)"),
              std::string::npos)
        << e.what();
  }
  // As deep as the limit is still JSON.
  const std::string limit = std::string(63, '[') + std::string(63, ']');
  EXPECT_EQ(parseJson(R"({"a": )" + limit + "}", "text").size(), 1u);
  EXPECT_THROW(parseJson(R"({"a": [)" + limit + "]}", "text"), IoError);
}

TEST(Recording, ReaderNamesADirectoryWithoutARecording) {
  const auto dir = test::freshTempDir();
  const std::string message = readError(dir);
  EXPECT_NE(message.find(dir.string()), std::string::npos) << message;
}

TEST(Recording, AJsonFileThatCannotBeOpenedSaysWhy) {
  // The reason is what the person acts on (no such file, permission denied): it is kept.
  const auto path = test::freshTempDir() / "gone" / "recording.json";
  try {
    readJsonFile(path);
    FAIL();
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string() + ": cannot open"), std::string::npos) << message;
    EXPECT_NE(message.find(std::strerror(ENOENT)), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace slicecap::io
