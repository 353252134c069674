// The camera's pose relative to the target: a rigid transform, target frame in mm.
#pragma once

#include <Eigen/Core>

#include "slicecap/core/grid.hpp"

namespace slicecap::vision {

/// \brief camera-from-target: a point X in the target frame (mm; origin at the window centre, x
/// right, y up, z out of the material) is at rotation * X + translationMm in the camera frame
/// (OpenCV: x right, y down, z forward). The same convention as cv::solvePnP's rvec/tvec.
struct Pose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translationMm = Eigen::Vector3d::Zero();

  /// \brief A target point in the camera frame.
  Eigen::Vector3d toCamera(const Eigen::Vector3d& targetPointMm) const {
    return rotation * targetPointMm + translationMm;
  }
  /// \brief The camera's optical centre in the target frame, mm.
  Eigen::Vector3d cameraCentreMm() const { return -rotation.transpose() * translationMm; }
};

/// \brief The pose of a camera at `centreMm` looking at `lookAtMm` (both in the target frame),
/// rolled so that the image's up direction is as close as possible to `upHint` (target frame);
/// then turned by `rollDeg` about the optical axis. upHint must not be parallel to the view.
Pose lookAtPose(const Eigen::Vector3d& centreMm, const Eigen::Vector3d& lookAtMm,
                const Eigen::Vector3d& upHint, double rollDeg = 0.0);

/// \brief The direction from a target point toward `fromMm` as elevation and azimuth in the target
/// frame (azimuth 0 along +x, counter-clockwise toward +y). `fromMm` must lie above the plane.
Direction directionFrom(const Eigen::Vector3d& targetPointMm, const Eigen::Vector3d& fromMm);

}  // namespace slicecap::vision
