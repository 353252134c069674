// The camera pose from marker corners on the target plane: homography start, Ceres refinement.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"

namespace slicecap::capture {

/// \brief A point of the target plane (mm) and where it was seen (pixels).
struct PlaneCorrespondence {
  Eigen::Vector2d targetMm;
  Eigen::Vector2d imagePx;
};

/// \brief A pose and how well it explains the corners.
struct PoseEstimate {
  vision::Pose pose;
  double residualRmsPx = 0.0;  ///< RMS reprojection error over all corners, pixels
};

/// \brief The homography H with to ~ H * from (homogeneous), by the normalised DLT over all
/// pairs (least squares). nullopt with fewer than 4 pairs, different counts or a degenerate fit.
std::optional<Eigen::Matrix3d> fitHomography(std::span<const Eigen::Vector2d> from,
                                             std::span<const Eigen::Vector2d> to);

/// \brief The pose minimising the reprojection error (with the camera's distortion) of all
/// correspondences at once. Starts from the homography of the undistorted points and from its
/// mirror (the plane's normal reflected about the line of sight: the two poses a near
/// fronto-parallel view cannot tell apart from a few corners) and keeps the one with the lower
/// residual. nullopt with fewer than 4 correspondences or a degenerate homography.
std::optional<PoseEstimate> estimatePlanarPose(std::span<const PlaneCorrespondence> points,
                                               const vision::CameraModel& camera);

}  // namespace slicecap::capture
