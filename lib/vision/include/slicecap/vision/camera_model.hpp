// A pinhole camera with OpenCV's five-coefficient radial-tangential distortion, in pixels.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

namespace slicecap::vision {

/// \brief Image size and pinhole intrinsics in pixels. Pixel centres sit at integer coordinates
/// (OpenCV's convention): the top-left pixel covers [-0.5, 0.5) x [-0.5, 0.5).
struct CameraIntrinsics {
  int widthPx = 1280;
  int heightPx = 720;
  double fxPx = 1000.0;  ///< focal length along x, pixels
  double fyPx = 1000.0;  ///< focal length along y, pixels
  double cxPx = 639.5;   ///< principal point, pixels
  double cyPx = 359.5;
  friend bool operator==(const CameraIntrinsics&, const CameraIntrinsics&) = default;
};

/// \brief OpenCV's distortion (k1, k2, p1, p2, k3) applied to normalised coordinates (x, y) =
/// (X / Z, Y / Z): r^2 = x^2 + y^2, radial 1 + k1 r^2 + k2 r^4 + k3 r^6, tangential
/// x += 2 p1 x y + p2 (r^2 + 2 x^2), y += p1 (r^2 + 2 y^2) + 2 p2 x y. All zero: no distortion.
struct Distortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
  bool isZero() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
  friend bool operator==(const Distortion&, const Distortion&) = default;
};

/// \brief A calibrated camera: camera frame x right, y down, z forward (OpenCV).
struct CameraModel {
  CameraIntrinsics intrinsics;
  Distortion distortion;
  friend bool operator==(const CameraModel&, const CameraModel&) = default;

  /// \brief False with a reason naming the field when the size or focal lengths are not positive,
  /// a value is not finite, or the distortion folds over inside the image (the distorted radius
  /// must grow with the undistorted one out to the image corners).
  bool isValid(std::string* error = nullptr) const;

  /// \brief Normalised coordinates after distortion (what the lens does).
  Eigen::Vector2d distort(const Eigen::Vector2d& normalised) const;
  /// \brief The inverse of distort, by fixed-point iteration (as cv::undistortPoints); converges
  /// to better than 1e-9 for any model that isValid() inside its image.
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted) const;
  /// \brief The same, started from `start` (a neighbouring pixel's result converges in 2 steps).
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted, const Eigen::Vector2d& start) const;

  /// \brief Pixel of a point in the camera frame (mm or any unit), or nullopt behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& pointInCamera) const;
  /// \brief Pixel of undistorted normalised coordinates.
  Eigen::Vector2d pixelOf(const Eigen::Vector2d& normalised) const;
  /// \brief Undistorted normalised coordinates of a pixel (the ray (x, y, 1) through it).
  Eigen::Vector2d normalisedOf(const Eigen::Vector2d& pixel) const;

  /// \brief The same camera seen through an image of `widthPx` x `heightPx` covering the same
  /// field of view (e.g. a RAW stream 2 x 2 binned from the sensor mode the processed stream was
  /// scaled from): focal lengths and principal point scaled, pixel centres kept at integer
  /// coordinates, distortion unchanged (it acts on normalised coordinates). Throws
  /// VisionError naming both sizes when the aspect ratios differ by more than 1 %
  /// (another crop of the sensor: calibrate at that size instead).
  CameraModel scaledTo(int widthPx, int heightPx) const;
};

/// \brief A typical Raspberry Pi camera module 3 at 1280 x 720 (wide 66 deg), with moderate barrel
/// distortion: what the virtual rig uses unless told otherwise.
CameraModel defaultSimulatedCamera();

}  // namespace slicecap::vision
