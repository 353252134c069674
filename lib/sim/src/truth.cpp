// truth.json writing and reading.
#include "slicecap/sim/truth.hpp"

#include <limits>
#include <nlohmann/json.hpp>

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/json_numbers.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::sim {

using nlohmann::json;

namespace {

json vec(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}
json rgb(const Rgb& v) {
  return json::array({v[0], v[1], v[2]});
}
json direction(const Direction& d) {
  return {{"theta_deg", d.thetaDeg}, {"phi_deg", d.phiDeg}};
}

// Reading: truth files are written by this code, so a malformed one is reported by the JSON
// library's own message (which names the key) with the file's path and, inside the frame list, the
// frame's index: a truth file has hundreds of frames with the same keys.
Eigen::Vector3d toVec(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}
Rgb toRgb(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}
Direction toDirection(const json& j) {
  return {j.at("theta_deg").get<double>(), j.at("phi_deg").get<double>()};
}

}  // namespace

void writeTruth(const std::filesystem::path& directory, const SweepTruth& truth) {
  json frames = json::array();
  for (const FrameTruth& f : truth.frames) {
    json rotation = json::array();
    for (int r = 0; r < 3; ++r)
      rotation.push_back({f.pose.rotation(r, 0), f.pose.rotation(r, 1), f.pose.rotation(r, 2)});
    frames.push_back(
        {{"file", f.file},
         {"timestamp_us", f.timestampUs},
         {"led_on", f.ledOn},
         {"exposure_us", f.exposureUs},
         {"gain", f.gain},
         {"slice_parameter_deg", f.sliceParameterDeg},
         {"pose", {{"rotation", rotation}, {"translation_mm", vec(f.pose.translationMm)}}},
         {"camera_centre_mm", vec(f.pose.cameraCentreMm())},
         {"view", direction(f.view)},
         {"camera_distance_mm", f.cameraDistanceMm},
         {"light_mm", vec(f.lightMm)},
         {"light", direction(f.light)},
         {"led_irradiance_w_per_m2", f.ledIrradiance},
         {"brdf", rgb(f.brdf)},
         {"expected_linear", rgb(f.expectedLinear)},
         {"motion_blur_px", f.motionBlurPx},
         {"occluded", f.occluded},
         {"aimed_off", f.aimedOff},
         {"markers_in_view", f.markersInView}});
  }
  const json root = {
      {"format", "slicecap-truth"},
      {"format_version", 1},
      {"material", truth.material},
      {"material_description", truth.materialDescription},
      {"slice",
       {{"kind", std::string(toString(truth.slice.id.kind))},
        {"theta_i_deg", truth.slice.id.elevations.thetaIDeg},
        {"theta_v_deg", truth.slice.id.elevations.thetaVDeg},
        {"alpha_deg", truth.slice.alphaDeg}}},
      {"radiometry",
       {{"led_intensity_w_per_sr", truth.ledIntensityWPerSr},
        {"sensor_response", truth.sensorResponse},
        {"ambient_irradiance_w_per_m2", truth.ambientIrradiance},
        {"model",
         "pixel_linear = sensor_response * exposure_s * gain * radiance; LED irradiance = "
         "intensity * cos(theta_i) / d_m^2; window radiance = brdf * E_led + brdf(light at the "
         "normal, view) * E_ambient; printed parts and desk: albedo / pi * (E_led + E_ambient); "
         "pose: X_camera = rotation * X_target + translation_mm (OpenCV camera axes)"}}},
      {"frames", frames}};
  io::writeJsonFileAtomically(directory / kTruthFile, root);
}

namespace {

io::RecordedSlice sliceOfTruth(const json& s, const std::filesystem::path& path) {
  const auto kind = parseSliceKind(s.at("kind").get<std::string>());
  if (!kind) throw io::IoError(path.string() + ": slice.kind: unknown kind");
  const auto elevationDeg = [&](const char* key) {
    const auto v = io::wholeNumberIn(s.at(key), 0, 89);
    if (!v)
      throw io::IoError(path.string() + ": slice." + key + ": expected a whole number of " +
                        "degrees in 0..89, got " + s.at(key).dump());
    return static_cast<int>(*v);
  };
  return {{*kind, {elevationDeg("theta_i_deg"), elevationDeg("theta_v_deg")}},
          s.at("alpha_deg").get<double>()};
}

std::vector<int> markersInViewOfFrame(const json& f, std::size_t index,
                                      const std::filesystem::path& path) {
  const json& markers = f.at("markers_in_view");
  if (!markers.is_array())
    throw io::IoError(path.string() + ": frames[" + std::to_string(index) +
                      "]: markers_in_view: not an array");
  std::vector<int> ids;
  for (const json& id : markers) {
    const auto v = io::wholeNumberIn(id, 0, std::numeric_limits<int>::max());
    if (!v)
      throw io::IoError(path.string() + ": frames[" + std::to_string(index) +
                        "]: markers_in_view: expected marker ids (whole numbers from 0), " +
                        "got " + id.dump());
    ids.push_back(static_cast<int>(*v));
  }
  return ids;
}

// Frame `index` of the list; the JSON library's exceptions pass through to the caller, which
// names the frame.
FrameTruth frameOfTruth(const json& f, std::size_t index, const std::filesystem::path& path) {
  FrameTruth ft;
  ft.file = f.at("file").get<std::string>();
  const auto timestampUs =
      io::wholeNumberIn(f.at("timestamp_us"), std::numeric_limits<std::int64_t>::min(),
                        std::numeric_limits<std::int64_t>::max());
  if (!timestampUs)
    throw io::IoError(path.string() + ": frames[" + std::to_string(index) +
                      "]: timestamp_us: expected a whole number, got " +
                      f.at("timestamp_us").dump());
  ft.timestampUs = *timestampUs;
  ft.ledOn = f.at("led_on").get<bool>();
  ft.exposureUs = f.at("exposure_us").get<double>();
  ft.gain = f.at("gain").get<double>();
  ft.sliceParameterDeg = f.at("slice_parameter_deg").get<double>();
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column)
      ft.pose.rotation(row, column) = f.at("pose").at("rotation").at(row).at(column).get<double>();
  }
  ft.pose.translationMm = toVec(f.at("pose").at("translation_mm"));
  ft.view = toDirection(f.at("view"));
  ft.cameraDistanceMm = f.at("camera_distance_mm").get<double>();
  ft.lightMm = toVec(f.at("light_mm"));
  ft.light = toDirection(f.at("light"));
  ft.ledIrradiance = f.at("led_irradiance_w_per_m2").get<double>();
  ft.brdf = toRgb(f.at("brdf"));
  ft.expectedLinear = toRgb(f.at("expected_linear"));
  ft.motionBlurPx = f.at("motion_blur_px").get<double>();
  ft.occluded = f.at("occluded").get<bool>();
  ft.aimedOff = f.at("aimed_off").get<bool>();
  ft.markersInView = markersInViewOfFrame(f, index, path);
  return ft;
}

}  // namespace

SweepTruth readTruth(const std::filesystem::path& directory) {
  const std::filesystem::path path = directory / kTruthFile;
  const json root = io::readJsonFile(path);
  try {
    SweepTruth t;
    t.material = root.at("material").get<std::string>();
    t.materialDescription = root.at("material_description").get<std::string>();
    t.slice = sliceOfTruth(root.at("slice"), path);
    const json& r = root.at("radiometry");
    t.ledIntensityWPerSr = r.at("led_intensity_w_per_sr").get<double>();
    t.sensorResponse = r.at("sensor_response").get<double>();
    t.ambientIrradiance = r.at("ambient_irradiance_w_per_m2").get<double>();
    const json& frames = root.at("frames");
    if (!frames.is_array()) throw io::IoError(path.string() + ": frames: not an array");
    for (std::size_t index = 0; index < frames.size(); ++index)
      try {
        t.frames.push_back(frameOfTruth(frames[index], index, path));
      } catch (const json::exception& e) {
        throw io::IoError(path.string() + ": frames[" + std::to_string(index) + "]: " + e.what());
      }
    return t;
  } catch (const json::exception& e) {
    throw io::IoError(path.string() + ": " + e.what());
  }
}

}  // namespace slicecap::sim
