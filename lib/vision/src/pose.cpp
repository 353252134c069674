// Building poses and reading directions off them.
#include "slicecap/vision/pose.hpp"

#include <Eigen/Geometry>

#include "slicecap/core/angles.hpp"

namespace slicecap::vision {

Pose lookAtPose(const Eigen::Vector3d& centreMm, const Eigen::Vector3d& lookAtMm,
                const Eigen::Vector3d& upHint, double rollDeg) {
  const Eigen::Vector3d forward = (lookAtMm - centreMm).normalized();  // camera z
  const Eigen::Vector3d down = -(upHint - upHint.dot(forward) * forward).normalized();  // camera y
  const Eigen::Vector3d right = down.cross(forward);                                      // camera x
  Eigen::Matrix3d targetFromCamera;
  targetFromCamera << right, down, forward;
  const Eigen::Matrix3d roll =
      Eigen::AngleAxisd(degToRad(rollDeg), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Pose pose;
  pose.rotation = roll * targetFromCamera.transpose();
  pose.translationMm = -pose.rotation * centreMm;
  return pose;
}

Direction directionFrom(const Eigen::Vector3d& targetPointMm, const Eigen::Vector3d& fromMm) {
  const Eigen::Vector3d d = fromMm - targetPointMm;
  return toDirection({d.x(), d.y(), d.z()});
}

}  // namespace slicecap::vision
