// Camera intrinsics and distortion from views of the target: Zhang's closed form, then Ceres.
#pragma once

#include <array>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/capture/planar_pose.hpp"
#include "slicecap/core/error.hpp"
#include "slicecap/vision/camera_model.hpp"

namespace slicecap::capture {

/// \brief Calibration is impossible from these views (too few, all fronto-parallel, diverging);
/// the message says which and what to record instead.
class CalibrationError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief The marker corners of one frame: target points (mm, z = 0) and where they were seen.
struct CalibrationView {
  std::string source;  ///< e.g. "rec/frame-00012.png", for messages and the report
  std::vector<PlaneCorrespondence> points;
};

/// \brief Options of calibrateCamera.
struct CalibrationSettings {
  int minViews = 4;  ///< fewer usable views: CalibrationError
  /// \brief Fewer corners than this in a view: the view is not used (a marker has four).
  int minPointsPerView = 32;
  /// \brief At most this many views enter the bundle adjustment, spread evenly over the input:
  /// neighbouring frames of a sweep add little and the cost grows with every view.
  int maxViews = 40;
  /// \brief Some view's target normal must be tilted at least this far from the optical axis,
  /// or the focal length is not observable (Zhang's degenerate case).
  double minTiltDeg = 10.0;
  /// \brief Views whose RMS reprojection error exceeds this many times the median view's are
  /// dropped and the adjustment run again (motion blur moves corners by a pixel or more).
  double outlierViewFactor = 3.0;
  /// \brief Huber loss scale, pixels: a corner off by more counts linearly, not quadratically.
  double robustLossPx = 1.0;
};

/// \brief The result: the camera, how well it explains the corners, how certain it is.
struct CameraCalibration {
  vision::CameraModel camera;
  double rmsReprojectionPx = 0.0;  ///< over all corners of the used views
  int viewsUsed = 0;
  int pointsUsed = 0;
  double maxTiltDeg = 0.0;  ///< the most oblique view's tilt
  /// \brief One standard deviation of fx, fy, cx, cy (px) and k1, k2, p1, p2, k3, from the
  /// Gauss-Newton covariance scaled by the residual variance (0 when it cannot be computed).
  std::array<double, 9> sigma{};
  /// \brief Distortion coefficients held at zero (indices into k1, k2, p1, p2, k3): k3, and k2
  /// too if needed, when the corners do not reach far enough out to determine them.
  std::vector<int> fixedDistortion;
  std::vector<std::string> usedSources;
  std::vector<double> viewRmsPx;            ///< per used view
  std::vector<std::string> droppedSources;  ///< views dropped as outliers
};

/// \brief Calibrates a camera of `widthPx` x `heightPx` from views of a planar target: a
/// homography per view, Zhang's closed-form intrinsics (zero skew), per-view poses, then a Ceres
/// bundle adjustment of fx, fy, cx, cy, the five distortion coefficients and every pose,
/// minimising the reprojection error with a Huber loss (k3, then k2, held at zero when the
/// corners stay near the image centre and the free fit folds the lens). Views with too few corners
/// are skipped. Throws CalibrationError when too few views remain, when every view is nearly
/// fronto-parallel, or when the solution is not a valid camera.
CameraCalibration calibrateCamera(const std::vector<CalibrationView>& views, int widthPx,
                                  int heightPx, const CalibrationSettings& settings = {});

/// \brief Detected marker corners of every frame of recordings (LED on or off; any slice or
/// none), at the detector's full resolution. All recordings must have the same image size, which
/// is returned through `widthPx` and `heightPx`. A frame that cannot be read is skipped and
/// counted in `unreadable`. Throws io::IoError for a bad recording.json, CalibrationError for
/// recordings of different sizes.
std::vector<CalibrationView> calibrationViewsOf(
    const std::vector<std::filesystem::path>& recordings, int* widthPx, int* heightPx,
    int* unreadable);

}  // namespace slicecap::capture
