// Target and camera JSON, and the JSON file helpers the recording shares.
#include "slicecap/io/target_json.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>

#include "input_file.hpp"
#include "json_fields.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::io {

using json_fields::Location;
using nlohmann::json;

json targetToJson(const vision::TargetGeometry& t) {
  json markers = json::array();
  for (const vision::Marker& m : t.markers) {
    json corners = json::array();
    for (const vision::PointMm& p : m.cornersMm)
      corners.push_back({p.xMm, p.yMm});
    markers.push_back({{"id", m.id}, {"size_mm", m.sizeMm}, {"corners_mm", corners}});
  }
  json patches = json::array();
  for (const vision::Patch& p : t.patches) {
    patches.push_back({{"name", p.name},
                       {"kind", vision::toString(p.kind)},
                       {"rect", json_fields::toJson(p.rect)},
                       {"albedo", json_fields::toJson(p.albedo)}});
  }
  return {{"name", t.name},
          {"units", "mm"},
          {"frame",
           "origin at the window centre, x to the right, y up, z out of the material; azimuth 0 "
           "along +x, counter-clockwise"},
          {"family", t.family},
          {"marker_corner_order",
           "as the AprilTag library reports them: bottom-left, bottom-right, top-right, top-left "
           "of an upright tag"},
          {"sheet", json_fields::toJson(t.sheet)},
          {"window", json_fields::toJson(t.window)},
          {"paper_albedo", json_fields::toJson(t.paperAlbedo)},
          {"ink_albedo", json_fields::toJson(t.inkAlbedo)},
          {"markers", markers},
          {"patches", patches}};
}

vision::TargetGeometry targetFromJson(const json& value, const std::string& file,
                                      const std::string& path) {
  namespace f = json_fields;
  const Location at{file, path};
  f::object(value, at);
  vision::TargetGeometry t;
  t.name = f::string(value, "name", at);
  if (f::string(value, "units", at) != "mm") (at / "units").fail("must be \"mm\"");
  t.family = f::string(value, "family", at);
  t.sheet = f::rect(value, "sheet", at);
  t.window = f::rect(value, "window", at);
  t.paperAlbedo = f::rgb(value, "paper_albedo", at);
  t.inkAlbedo = f::rgb(value, "ink_albedo", at);
  const json& markers = f::array(value, "markers", at);
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const Location here = (at / "markers")[i];
    f::object(markers[i], here);
    vision::Marker m;
    const std::int64_t id = f::integer(markers[i], "id", here);
    // Checked before the cast, which would take 4294967299 for tag 3.
    if (!std::in_range<int>(id))
      (here / "id").fail("expected a tag36h11 id, got " + std::to_string(id));
    m.id = static_cast<int>(id);
    m.sizeMm = f::positiveNumber(markers[i], "size_mm", here);
    const json& corners = f::array(markers[i], "corners_mm", here);
    if (corners.size() != 4) (here / "corners_mm").fail("expected 4 corners");
    for (std::size_t k = 0; k < 4; ++k) {
      if (!corners[k].is_array() || corners[k].size() != 2 || !corners[k][0].is_number() ||
          !corners[k][1].is_number())
        ((here / "corners_mm")[k]).fail("expected [x_mm, y_mm]");
      m.cornersMm[k] = {corners[k][0].get<double>(), corners[k][1].get<double>()};
    }
    t.markers.push_back(m);
  }
  const json& patches = f::array(value, "patches", at);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Location here = (at / "patches")[i];
    f::object(patches[i], here);
    vision::Patch p;
    p.name = f::string(patches[i], "name", here);
    const std::string kind = f::string(patches[i], "kind", here);
    if (kind != "white" && kind != "black") (here / "kind").fail("expected \"white\" or \"black\"");
    p.kind = kind == "white" ? vision::PatchKind::White : vision::PatchKind::Black;
    p.rect = f::rect(patches[i], "rect", here);
    p.albedo = f::rgb(patches[i], "albedo", here);
    t.patches.push_back(p);
  }
  if (const auto problem = vision::findTargetProblem(t)) at.fail(*problem);
  return t;
}

void writeTargetJson(const std::filesystem::path& path, const vision::TargetGeometry& target) {
  writeJsonFileAtomically(path, targetToJson(target));
}

vision::TargetGeometry readTargetJson(const std::filesystem::path& path) {
  return targetFromJson(readJsonFile(path), path.string());
}

json cameraToJson(const vision::CameraModel& c) {
  const vision::CameraIntrinsics& k = c.intrinsics;
  const vision::Distortion& d = c.distortion;
  return {{"width_px", k.widthPx},
          {"height_px", k.heightPx},
          {"fx_px", k.fxPx},
          {"fy_px", k.fyPx},
          {"cx_px", k.cxPx},
          {"cy_px", k.cyPx},
          {"distortion",
           {{"model", "opencv-radtan5"},
            {"k1", d.k1},
            {"k2", d.k2},
            {"p1", d.p1},
            {"p2", d.p2},
            {"k3", d.k3}}}};
}

vision::CameraModel cameraFromJson(const json& value, const std::string& file,
                                   const std::string& path) {
  namespace f = json_fields;
  const Location at{file, path};
  f::object(value, at);
  vision::CameraModel c;
  const auto size = [&](const char* key) {
    const std::int64_t v = f::integer(value, key, at);
    // Frames of this size are allocated from it (the virtual rig renders them): a typo must be
    // an error naming the file, not an allocation failure.
    if (v <= 0 || v > kMaxCameraSidePx)
      (at / key).fail("expected a positive pixel count up to " + std::to_string(kMaxCameraSidePx) +
                      ", got " + std::to_string(v));
    return static_cast<int>(v);
  };
  c.intrinsics = {size("width_px"),
                  size("height_px"),
                  f::positiveNumber(value, "fx_px", at),
                  f::positiveNumber(value, "fy_px", at),
                  f::number(value, "cx_px", at),
                  f::number(value, "cy_px", at)};
  const json& d = f::object(f::member(value, "distortion", at), at / "distortion");
  const Location dAt = at / "distortion";
  if (f::string(d, "model", dAt) != "opencv-radtan5")
    (dAt / "model").fail("only \"opencv-radtan5\" (k1, k2, p1, p2, k3) is supported");
  c.distortion = {f::number(d, "k1", dAt), f::number(d, "k2", dAt), f::number(d, "p1", dAt),
                  f::number(d, "p2", dAt), f::number(d, "k3", dAt)};
  std::string problem;
  if (!c.isValid(&problem)) at.fail(problem);
  return c;
}

namespace {

// json::parse with errors naming `source`: also out_of_range, nlohmann's error for a number
// beyond a double (1e400), and nesting deeper than kMaxJsonDepth (the parser itself does not
// recurse, but dump does, in the readers' error messages).
template <typename Input>
json parseNamed(Input&& input, const std::string& source) {
  const json::parser_callback_t limitDepth = [&](int depth, json::parse_event_t event, json&) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth)
      throw IoError(source + ": not valid JSON (arrays and objects nested deeper than " +
                    std::to_string(kMaxJsonDepth) + " levels)");
    return true;
  };
  try {
    return json::parse(std::forward<Input>(input), limitDepth);
  } catch (const json::exception& e) {
    throw IoError(source + ": not valid JSON (" + e.what() + ")");
  }
}

}  // namespace

json readJsonFile(const std::filesystem::path& path) {
  refuseDirectory(path, "a JSON file");
  errno = 0;
  std::ifstream in(path);
  // The reason (no such file, permission denied) is what the person needs to act on.
  if (!in)
    throw IoError(path.string() + ": cannot open" +
                  (errno ? std::string(" (") + std::strerror(errno) + ")" : std::string()));
  return parseNamed(in, path.string());
}

json parseJson(std::string_view text, const std::string& source) {
  return parseNamed(text, source);
}

void writeJsonFileAtomically(const std::filesystem::path& path, const json& value) {
  writeFileAtomically(path, value.dump(1) + "\n");
}

}  // namespace slicecap::io
