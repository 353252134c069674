// recording.json: reading with field-level validation, atomic writing, frame-by-frame appends.
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/recording.hpp"

#include <algorithm>
#include <stdexcept>

#include "json_fields.hpp"
#include "slicecap/core/core_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::io {

RecordedDecoding RecordedDecoding::defaultFor(PixelEncoding encoding) {
  return {encoding == PixelEncoding::Srgb8 ? Kind::Srgb : Kind::Linear, std::nullopt};
}

std::optional<ToneCurve> RecordedDecoding::toneCurve() const {
  if (kind == Kind::MeasuredCurve) return curve;
  if (kind == Kind::Linear) return ToneCurve::linear();
  return std::nullopt;
}

bool operator==(const RecordedDecoding& a, const RecordedDecoding& b) {
  if (a.kind != b.kind || a.curve.has_value() != b.curve.has_value() || a.black16 != b.black16)
    return false;
  return !a.curve || (a.curve->name() == b.curve->name() && a.curve->points() == b.curve->points());
}

std::string toString(RecordedDecoding::Kind kind) {
  switch (kind) {
    case RecordedDecoding::Kind::Srgb:
      return "srgb";
    case RecordedDecoding::Kind::MeasuredCurve:
      return "measured-curve";
    case RecordedDecoding::Kind::Linear:
      return "linear";
  }
  return "srgb";
}

using json_fields::Location;
using nlohmann::json;

namespace {

constexpr const char* kFormatName = "slicecap-recording";

json frameToJson(const RecordedFrame& f) {
  json out = {{"file", f.file},
              {"timestamp_us", f.timestampUs},
              {"led_on", f.ledOn},
              {"exposure_us", f.exposureUs},
              {"gain", f.gain}};
  if (f.exposureLevel) out["exposure_level"] = *f.exposureLevel;
  if (f.ledExposure) {
    const RecordedLedExposure& e = *f.ledExposure;
    json changes = json::array();
    for (const auto& [timeUs, on] : e.changes) changes.push_back({{"time_us", timeUs}, {"on", on}});
    out["led_exposure"] = {{"row0_start_us", e.row0StartUs}, {"line_time_us", e.lineTimeUs},
                           {"exposure_us", e.exposureUs},    {"guard_us", e.guardUs},
                           {"on_at_start", e.onAtStart},     {"changes", changes}};
  }
  return out;
}

RecordedLedExposure ledExposureFromJson(const json& value, const Location& at) {
  namespace f = json_fields;
  f::object(value, at);
  RecordedLedExposure e;
  e.row0StartUs = f::integer(value, "row0_start_us", at);
  e.lineTimeUs = f::number(value, "line_time_us", at);
  if (!(e.lineTimeUs >= 0 && e.lineTimeUs < 1e6)) (at / "line_time_us").fail("must be in 0..1e6");
  e.exposureUs = f::positiveNumber(value, "exposure_us", at);
  e.guardUs = f::number(value, "guard_us", at);
  if (!(e.guardUs >= 0 && e.guardUs < 1e6)) (at / "guard_us").fail("must be in 0..1e6");
  e.onAtStart = f::boolean(value, "on_at_start", at);
  const json& changes = f::array(value, "changes", at);
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const Location here = (at / "changes")[i];
    f::object(changes[i], here);
    const std::int64_t timeUs = f::integer(changes[i], "time_us", here);
    if (!e.changes.empty() && timeUs < e.changes.back().first)
      (here / "time_us").fail("switches must be in time order");
    e.changes.emplace_back(timeUs, f::boolean(changes[i], "on", here));
  }
  return e;
}

// The version a manifest is written at: the recording's, raised to what its fields need (a
// decoding needs a reader that knows it, version 2; a decoding's black, version 3).
int manifestVersion(const Recording& r) {
  if (r.decoding && r.decoding->black16 != 0) return std::max(r.formatVersion, 3);
  if (r.decoding) return std::max(r.formatVersion, 2);
  return r.formatVersion;
}

json toJson(const Recording& r) {
  json frames = json::array();
  for (const RecordedFrame& f : r.frames)
    frames.push_back(frameToJson(f));
  json out = {{"format", kFormatName},
              {"format_version", manifestVersion(r)},
              {"created_by", r.createdBy},
              {"camera", r.calibrationFile ? json{{"calibration_file", *r.calibrationFile}}
                                           : cameraToJson(r.camera)},
              {"pixel_encoding", std::string(toString(r.encoding))}};
  if (r.decoding) {
    out["decoding"] = toString(r.decoding->kind);
    if (r.decoding->curve) {
      json points = json::array();
      for (const auto& [linear, encoded] : r.decoding->curve->points())
        points.push_back({linear, encoded});
      out["decoding_curve"] = {{"name", r.decoding->curve->name()}, {"points", points}};
    }
    if (r.decoding->black16 != 0) out["decoding_black16"] = r.decoding->black16;
  }
  if (r.slice) {
    out["slice"] = {{"kind", std::string(toString(r.slice->id.kind))},
                    {"theta_i_deg", r.slice->id.elevations.thetaIDeg},
                    {"theta_v_deg", r.slice->id.elevations.thetaVDeg},
                    {"alpha_deg", r.slice->alphaDeg}};
  }
  if (r.roomLightUnseenMm) out["room_light_unseen_mm"] = *r.roomLightUnseenMm;
  out["target"] = targetToJson(r.target);
  out["frames"] = frames;
  return out;
}

// A frame file must stay inside the recording: relative, no "..".
bool isPlainRelative(const std::string& file) {
  const std::filesystem::path p(file);
  if (file.empty() || p.is_absolute()) return false;
  for (const auto& part : p) {
    if (part == "..") return false;
  }
  return true;
}

RecordedSlice sliceFromJson(const json& value, const Location& at) {
  namespace f = json_fields;
  f::object(value, at);
  const std::string kindText = f::string(value, "kind", at);
  const auto kind = parseSliceKind(kindText);
  // A recording is one sweep; a point slice is no sweep the rig can make.
  if (!kind || *kind == SliceKind::Point)
    (at / "kind").fail("expected \"axial\" or \"diagonal\", got \"" + kindText + "\"");
  RecordedSlice slice;
  slice.id.kind = *kind;
  for (const auto& [key, field] : {std::pair{"theta_i_deg", &slice.id.elevations.thetaIDeg},
                                   std::pair{"theta_v_deg", &slice.id.elevations.thetaVDeg}}) {
    const std::int64_t theta = f::integer(value, key, at);
    if (theta < 0 || theta >= 90) (at / key).fail("expected whole degrees in 0..89");
    *field = static_cast<int>(theta);
  }
  slice.alphaDeg = f::number(value, "alpha_deg", at);
  if (slice.alphaDeg <= -180.0 || slice.alphaDeg > 180.0)
    (at / "alpha_deg").fail("expected (-180, 180]");
  return slice;
}

// `decoding` (absent: the encoding's default) and, for a measured curve, `decoding_curve`:
// {name, points: [[linear, encoded]...]}; a linear16 recording's `decoding_black16`.
RecordedDecoding decodingFromJson(const json& root, PixelEncoding encoding, const Location& at) {
  namespace f = json_fields;
  const std::string text = root.contains("decoding")
                               ? f::string(root, "decoding", at)
                               : toString(RecordedDecoding::defaultFor(encoding).kind);
  RecordedDecoding decoding;
  if (text == "srgb") decoding.kind = RecordedDecoding::Kind::Srgb;
  else if (text == "measured-curve") decoding.kind = RecordedDecoding::Kind::MeasuredCurve;
  else if (text == "linear") decoding.kind = RecordedDecoding::Kind::Linear;
  else (at / "decoding").fail("expected \"srgb\", \"measured-curve\" or \"linear\", got \"" + text + "\"");
  if (encoding == PixelEncoding::Linear16 && decoding.kind != RecordedDecoding::Kind::Linear)
    (at / "decoding").fail("linear16 frames are linear, not \"" + text + "\"");
  if (root.contains("decoding_black16")) {
    if (encoding != PixelEncoding::Linear16)
      (at / "decoding_black16").fail("only linear16 frames have a black above 0");
    const std::int64_t black = f::integer(root, "decoding_black16", at);
    if (black < 0 || black > 65534) (at / "decoding_black16").fail("expected 0..65534");
    decoding.black16 = static_cast<std::uint16_t>(black);
  }
  if (decoding.kind != RecordedDecoding::Kind::MeasuredCurve) return decoding;
  const Location curveAt = at / "decoding_curve";
  const json& curve = f::object(f::member(root, "decoding_curve", at), curveAt);
  const std::string name = f::string(curve, "name", curveAt);
  const json& points = f::array(curve, "points", curveAt);
  std::vector<std::pair<double, double>> values;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const json& point = points[i];
    if (!point.is_array() || point.size() != 2 || !point[0].is_number() || !point[1].is_number())
      (curveAt / "points")[i].fail("expected [linear, encoded]");
    values.emplace_back(point[0].get<double>(), point[1].get<double>());
  }
  try {
    decoding.curve = ToneCurve(name, std::move(values));
  } catch (const CoreError& error) {
    (curveAt / "points").fail(error.what());
  }
  return decoding;
}

}  // namespace

std::filesystem::path framePath(const std::filesystem::path& directory,
                                const RecordedFrame& frame) {
  return directory / frame.file;
}

namespace {

// The manifest's format, version and creator.
void readManifestHeader(const json& root, const Location& at, Recording& r) {
  namespace f = json_fields;
  if (f::string(root, "format", at) != kFormatName)
    (at / "format").fail(std::string("expected \"") + kFormatName + "\"");
  const std::int64_t version = f::integer(root, "format_version", at);
  if (version < 1 || version > kRecordingFormatVersion)
    (at / "format_version")
        .fail("version " + std::to_string(version) + " is not readable by this build (reads 1.." +
              std::to_string(kRecordingFormatVersion) + ")");
  r.formatVersion = static_cast<int>(version);
  if (root.contains("created_by")) r.createdBy = f::string(root, "created_by", at);
}

// The camera, inline or from its calibration file.
void readCamera(const json& root, const Location& at, const std::filesystem::path& directory,
                const std::filesystem::path& manifest, Recording& r) {
  namespace f = json_fields;
  const json& camera = f::object(f::member(root, "camera", at), at / "camera");
  if (camera.contains("calibration_file")) {
    const std::string file = f::string(camera, "calibration_file", at / "camera");
    // Unlike frames, a calibration is shared by the recordings of a session (or a camera): it
    // may sit outside the directory ("../camera.json") or anywhere (an absolute path).
    if (file.empty()) (at / "camera" / "calibration_file").fail("must not be empty");
    const std::filesystem::path calibration = directory / file;
    if (!std::filesystem::exists(calibration))
      (at / "camera" / "calibration_file").fail("'" + calibration.string() + "' does not exist");
    r.calibrationFile = file;
    r.camera = cameraFromJson(readJsonFile(calibration), calibration.string());
  } else {
    r.camera = cameraFromJson(camera, manifest.string(), "camera");
  }
}

// Frame `here` of the list; `previous` is the recording's frames read so far.
RecordedFrame frameFromJson(const json& value, const Location& here,
                            const std::filesystem::path& directory,
                            const std::vector<RecordedFrame>& previous) {
  namespace f = json_fields;
  f::object(value, here);
  RecordedFrame frame;
  frame.file = f::string(value, "file", here);
  if (!isPlainRelative(frame.file))
    (here / "file").fail("must be a relative path inside the recording");
  if (!std::filesystem::is_regular_file(directory / frame.file))
    (here / "file").fail("'" + (directory / frame.file).string() + "' does not exist");
  frame.timestampUs = f::integer(value, "timestamp_us", here);
  if (!previous.empty() && frame.timestampUs <= previous.back().timestampUs)
    (here / "timestamp_us")
        .fail("timestamps must increase (previous frame: " +
              std::to_string(previous.back().timestampUs) + ")");
  frame.ledOn = f::boolean(value, "led_on", here);
  frame.exposureUs = f::positiveNumber(value, "exposure_us", here);
  frame.gain = f::positiveNumber(value, "gain", here);
  if (value.contains("exposure_level")) {
    const std::int64_t level = f::integer(value, "exposure_level", here);
    if (level < 0 || level >= kMaxExposureLevels)
      (here / "exposure_level")
          .fail("expected 0.." + std::to_string(kMaxExposureLevels - 1) + ", got " +
                std::to_string(level));
    frame.exposureLevel = static_cast<int>(level);
  }
  if (value.contains("led_exposure"))
    frame.ledExposure = ledExposureFromJson(value["led_exposure"], here / "led_exposure");
  return frame;
}

}  // namespace

Recording readRecording(const std::filesystem::path& input) {
  namespace f = json_fields;
  const bool isFile = std::filesystem::is_regular_file(input);
  const std::filesystem::path directory = isFile ? input.parent_path() : input;
  const std::filesystem::path manifest = isFile ? input : input / kRecordingManifest;
  if (!std::filesystem::exists(manifest))
    throw IoError(manifest.string() + ": no recording here (" + kRecordingManifest +
                  " is missing)");
  const json root = readJsonFile(manifest);
  const Location at{manifest.string(), ""};
  f::object(root, at);
  Recording r;
  readManifestHeader(root, at, r);
  readCamera(root, at, directory, manifest, r);

  const std::string encoding = f::string(root, "pixel_encoding", at);
  const auto parsed = parsePixelEncoding(encoding);
  if (!parsed)
    (at / "pixel_encoding").fail("expected \"srgb8\" or \"linear16\", got \"" + encoding + "\"");
  r.encoding = *parsed;
  if (root.contains("decoding") || root.contains("decoding_black16"))
    r.decoding = decodingFromJson(root, r.encoding, at);
  if (root.contains("slice") && !root["slice"].is_null())
    r.slice = sliceFromJson(root["slice"], at / "slice");
  if (root.contains("room_light_unseen_mm")) {
    const double unseenMm = f::number(root, "room_light_unseen_mm", at);
    if (!(unseenMm > 0.0 && unseenMm <= 1000.0))
      (at / "room_light_unseen_mm").fail("expected a distance in mm above 0 and up to 1000");
    r.roomLightUnseenMm = unseenMm;
  }
  r.target = targetFromJson(f::member(root, "target", at), manifest.string(), "target");

  const json& frames = f::array(root, "frames", at);
  for (std::size_t i = 0; i < frames.size(); ++i)
    r.frames.push_back(frameFromJson(frames[i], (at / "frames")[i], directory, r.frames));
  return r;
}

void writeRecordingManifest(const std::filesystem::path& directory, const Recording& recording) {
  writeJsonFileAtomically(directory / kRecordingManifest, toJson(recording));
}

RecordingWriter::RecordingWriter(std::filesystem::path directory, Recording header)
    : directory_(std::move(directory)), recording_(std::move(header)) {
  if (!recording_.frames.empty())
    throw IoError("RecordingWriter: the header must not list frames yet");
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error)
    throw IoError(directory_.string() + ": cannot create directory (" + error.message() + ")");
  if (std::filesystem::exists(directory_ / kRecordingManifest))
    throw IoError(directory_.string() + ": already holds a recording; refusing to overwrite it");
  recording_.formatVersion = manifestVersion(recording_);  // what a reader will read back
  writeRecordingManifest(directory_, recording_);
}

RecordingWriter RecordingWriter::resume(const std::filesystem::path& directory) {
  RecordingWriter writer;
  writer.directory_ = directory;
  writer.recording_ = readRecording(directory);
  return writer;
}

const RecordedFrame& RecordingWriter::append(const Image& image, RecordedFrame frame) {
  const vision::CameraIntrinsics& k = recording_.camera.intrinsics;
  if (!image.isValid() || image.width != k.widthPx || image.height != k.heightPx ||
      (image.channels != 1 && image.channels != 3) ||
      image.bitDepth != bitDepthOf(recording_.encoding))
    throw IoError(
        "RecordingWriter: frame " + std::to_string(recording_.frames.size()) + " is not a " +
        std::to_string(k.widthPx) + " x " + std::to_string(k.heightPx) + " gray or RGB image of " +
        std::string(toString(recording_.encoding)));
  if (!recording_.frames.empty() && frame.timestampUs <= recording_.frames.back().timestampUs)
    throw IoError("RecordingWriter: timestamps must increase");
  char name[32];
  std::snprintf(name, sizeof name, "frame-%05zu.png", recording_.frames.size());
  frame.file = name;
  writePng(directory_ / frame.file, image);
  recording_.frames.push_back(frame);
  try {
    writeRecordingManifest(directory_, recording_);
  } catch (...) {
    recording_.frames.pop_back();
    throw;
  }
  return recording_.frames.back();
}

}  // namespace slicecap::io
