// Projection and (iterative) undistortion with OpenCV's radial-tangential model.
#include "slicecap/vision/camera_model.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "slicecap/vision/camera_scaling.hpp"
#include "slicecap/vision/vision_error.hpp"

namespace slicecap::vision {
namespace {

bool fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

}  // namespace

bool CameraModel::isValid(std::string* error) const {
  const CameraIntrinsics& k = intrinsics;
  if (k.widthPx <= 0 || k.heightPx <= 0) return fail(error, "width_px and height_px must be > 0");
  for (const auto& [name, value] : {std::pair{"fx_px", k.fxPx}, std::pair{"fy_px", k.fyPx}}) {
    if (!std::isfinite(value) || value <= 0.0)
      return fail(error, std::string(name) + " must be a positive number");
  }
  for (const auto& [name, value] : {std::pair{"cx_px", k.cxPx}, std::pair{"cy_px", k.cyPx}}) {
    if (!std::isfinite(value)) return fail(error, std::string(name) + " must be finite");
  }
  const Distortion& d = distortion;
  for (const auto& [name, value] :
       {std::pair{"k1", d.k1}, std::pair{"k2", d.k2}, std::pair{"p1", d.p1}, std::pair{"p2", d.p2},
        std::pair{"k3", d.k3}}) {
    if (!std::isfinite(value))
      return fail(error, std::string("distortion ") + name + " is not finite");
  }
  // The radial factor's derivative d(r (1 + k1 r^2 + k2 r^4 + k3 r^6))/dr must stay positive up to
  // the farthest image corner (with margin), or undistortion is ambiguous.
  const double cornerX = std::max(k.cxPx, k.widthPx - k.cxPx) / k.fxPx;
  const double cornerY = std::max(k.cyPx, k.heightPx - k.cyPx) / k.fyPx;
  const double rMax = 1.5 * std::hypot(cornerX, cornerY);
  for (int i = 1; i <= 100; ++i) {
    const double r2 = std::pow(rMax * i / 100.0, 2);
    const double slope = 1 + 3 * d.k1 * r2 + 5 * d.k2 * r2 * r2 + 7 * d.k3 * r2 * r2 * r2;
    if (slope <= 0.05) return fail(error, "distortion folds over inside the image (k1, k2, k3)");
  }
  return true;
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& n) const {
  const Distortion& d = distortion;
  const double x = n.x(), y = n.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  return {x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x),
          y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y};
}

Eigen::Vector2d CameraModel::undistort(const Eigen::Vector2d& distorted) const {
  return undistort(distorted, distorted);
}

Eigen::Vector2d CameraModel::undistort(const Eigen::Vector2d& distorted,
                                       const Eigen::Vector2d& start) const {
  if (distortion.isZero()) return distorted;
  // Newton's method on distort(n) = distorted with the analytic Jacobian.
  const Distortion& d = distortion;
  Eigen::Vector2d n = start;
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Eigen::Vector2d residual = distort(n) - distorted;
    if (residual.norm() < 1e-14) break;
    const double x = n.x(), y = n.y(), r2 = x * x + y * y;
    const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double dRadial = d.k1 + r2 * (2 * d.k2 + 3 * r2 * d.k3);  // d radial / d r2
    Eigen::Matrix2d jacobian;
    jacobian << radial + 2 * x * x * dRadial + 2 * d.p1 * y + 6 * d.p2 * x,
        2 * x * y * dRadial + 2 * d.p1 * x + 2 * d.p2 * y,
        2 * x * y * dRadial + 2 * d.p1 * x + 2 * d.p2 * y,
        radial + 2 * y * y * dRadial + 6 * d.p1 * y + 2 * d.p2 * x;
    n -= jacobian.inverse() * residual;
  }
  return n;
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& p) const {
  if (!(p.z() > 0.0)) return std::nullopt;
  return pixelOf({p.x() / p.z(), p.y() / p.z()});
}

Eigen::Vector2d CameraModel::pixelOf(const Eigen::Vector2d& normalised) const {
  const Eigen::Vector2d d = distort(normalised);
  return {intrinsics.fxPx * d.x() + intrinsics.cxPx, intrinsics.fyPx * d.y() + intrinsics.cyPx};
}

Eigen::Vector2d CameraModel::normalisedOf(const Eigen::Vector2d& pixel) const {
  return undistort({(pixel.x() - intrinsics.cxPx) / intrinsics.fxPx,
                    (pixel.y() - intrinsics.cyPx) / intrinsics.fyPx});
}

std::optional<std::string> scalingProblem(const CameraModel& camera, int widthPx, int heightPx) {
  const CameraIntrinsics& from = camera.intrinsics;
  const auto size = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
  if (widthPx <= 0 || heightPx <= 0)
    return "camera model: cannot scale to " + size(widthPx, heightPx);
  const double sx = double(widthPx) / from.widthPx, sy = double(heightPx) / from.heightPx;
  if (std::abs(sx / sy - 1.0) > 0.01)
    return "camera model: a " + size(from.widthPx, from.heightPx) +
           " calibration does not scale to " + size(widthPx, heightPx) +
           " frames (another aspect ratio: another crop of the sensor); "
           "calibrate the camera at " + size(widthPx, heightPx);
  return std::nullopt;
}

CameraModel CameraModel::scaledTo(int widthPx, int heightPx) const {
  if (const std::optional<std::string> problem = scalingProblem(*this, widthPx, heightPx))
    throw VisionError(*problem);
  const CameraIntrinsics& from = intrinsics;
  const double sx = double(widthPx) / from.widthPx, sy = double(heightPx) / from.heightPx;
  CameraModel scaled = *this;
  // Pixel centres at integer coordinates: the image's edge (-0.5) maps to the new edge.
  scaled.intrinsics = {widthPx,
                       heightPx,
                       from.fxPx * sx,
                       from.fyPx * sy,
                       (from.cxPx + 0.5) * sx - 0.5,
                       (from.cyPx + 0.5) * sy - 0.5};
  return scaled;
}

CameraModel defaultSimulatedCamera() {
  CameraModel camera;
  camera.intrinsics = {1280, 720, 985.0, 983.5, 643.2, 357.9};
  camera.distortion = {-0.085, 0.072, 0.0006, -0.0004, -0.011};
  return camera;
}

}  // namespace slicecap::vision
