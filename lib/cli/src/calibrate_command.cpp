// `slicecap calibrate`: camera intrinsics and distortion from recordings of the target.
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/capture/camera_calibration.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::cli {
namespace {

int wholeNumber(const ParsedArgs& args, const std::string& name, int fallback, int minimum) {
  const double value = args.number(name, fallback);
  if (value != std::floor(value) || value < minimum)
    throw UsageError("--" + name + " must be a whole number >= " + std::to_string(minimum));
  return static_cast<int>(value);
}

// The distortion coefficients the adjustment held at zero, by name.
std::vector<std::string> fixedNames(const capture::CameraCalibration& c) {
  static const char* names[5] = {"k1", "k2", "p1", "p2", "k3"};
  std::vector<std::string> out;
  for (int i : c.fixedDistortion)
    out.push_back(names[i]);
  return out;
}

nlohmann::json calibrationJson(const capture::CameraCalibration& c,
                               const std::vector<std::string>& recordings) {
  static const char* names[9] = {"fx_px", "fy_px", "cx_px", "cy_px", "k1", "k2", "p1", "p2", "k3"};
  nlohmann::json sigma;
  for (int i = 0; i < 9; ++i)
    sigma[names[i]] = c.sigma[i];
  nlohmann::json views = nlohmann::json::array();
  for (std::size_t i = 0; i < c.usedSources.size(); ++i)
    views.push_back({{"frame", c.usedSources[i]}, {"rms_px", c.viewRmsPx[i]}});
  return {{"method", "zhang closed form + bundle adjustment (huber loss)"},
          {"rms_reprojection_px", c.rmsReprojectionPx},
          {"views_used", c.viewsUsed},
          {"corners_used", c.pointsUsed},
          {"max_tilt_deg", c.maxTiltDeg},
          {"sigma", sigma},
          {"held_at_zero", fixedNames(c)},
          {"recordings", recordings},
          {"views", views},
          {"dropped_views", c.droppedSources}};
}

int run(const ParsedArgs& args, Streams& io) {
  const std::filesystem::path output = args.required("output");
  capture::CalibrationSettings settings;
  settings.maxViews = wholeNumber(args, "max-views", settings.maxViews, 4);
  settings.minPointsPerView = wholeNumber(args, "min-corners", settings.minPointsPerView, 8);
  std::vector<std::filesystem::path> recordings(args.positional.begin(), args.positional.end());
  refuseClashingPaths(recordingInputs(recordings), {{"-o", output}});
  int width = 0, height = 0, unreadable = 0;
  const auto views = capture::calibrationViewsOf(recordings, &width, &height, &unreadable);
  if (unreadable > 0)
    io.err << "warning: " << unreadable << " frames could not be read (missing, corrupt or of "
           << "the wrong size) and were skipped\n";
  const capture::CameraCalibration c = capture::calibrateCamera(views, width, height, settings);
  nlohmann::json file = io::cameraToJson(c.camera);
  file["calibration"] = calibrationJson(c, args.positional);
  io::writeJsonFileAtomically(output, file);
  const auto& k = c.camera.intrinsics;
  const auto& d = c.camera.distortion;
  io.out << std::fixed << std::setprecision(2) << "camera " << k.widthPx << " x " << k.heightPx
         << ": fx " << k.fxPx << " +- " << c.sigma[0] << ", fy " << k.fyPx << " +- " << c.sigma[1]
         << ", cx " << k.cxPx << " +- " << c.sigma[2] << ", cy " << k.cyPx << " +- " << c.sigma[3]
         << " px\n"
         << std::setprecision(5) << "distortion k1 " << d.k1 << ", k2 " << d.k2 << ", p1 " << d.p1
         << ", p2 " << d.p2 << ", k3 " << d.k3;
  const std::vector<std::string> fixed = fixedNames(c);
  for (std::size_t i = 0; i < fixed.size(); ++i)
    io.out << (i == 0 ? " (held at 0: " : ", ") << fixed[i];
  if (!fixed.empty()) io.out << "; the corners do not reach far enough out to fit them)";
  io.out << "\n"
         << std::setprecision(3) << "RMS reprojection error " << c.rmsReprojectionPx << " px over "
         << c.pointsUsed << " corners in " << c.viewsUsed << " of " << views.size() << " frames ("
         << c.droppedSources.size() << " dropped as outliers; most oblique view "
         << std::setprecision(1) << c.maxTiltDeg << " deg)\n"
         << "wrote " << output.string() << "\n";
  return 0;
}

}  // namespace

Command calibrateCommand() {
  return {{"calibrate",
           "RECORDING... -o CAMERA.json [--max-views N] [--min-corners N]",
           "Calibrate the camera from recordings of the target (any sweeps, or frames taken for\n"
           "the purpose; LED on or off): its marker corners make a calibration board. Fits a\n"
           "homography per frame, Zhang's closed-form intrinsics (zero skew), then a bundle\n"
           "adjustment (Ceres, Huber loss) of fx, fy, cx, cy, the distortion k1, k2, p1, p2, k3\n"
           "and every frame's pose, minimising the reprojection error. Uses frames with at least\n"
           "--min-corners corners, at most --max-views of them spread over the recordings. Record\n"
           "from several elevations (e.g. 30 and 75 deg sweeps): fronto-parallel views alone\n"
           "leave the focal length unobservable (an error). Writes the camera JSON a\n"
           "recording.json's camera.calibration_file can name, with the RMS reprojection error\n"
           "and each parameter's standard deviation; prints them.",
           {{"output", 'o', "CAMERA.json", "the calibrated camera (required)"},
            {"max-views", 0, "N", "at most this many frames in the adjustment (40)"},
            {"min-corners", 0, "N", "frames with fewer marker corners are not used (32)"}},
           1,
           64},
          run};
}

}  // namespace slicecap::cli
