// Planar PnP: DLT homography on undistorted normalised points, decomposition, Ceres refinement.
#include "slicecap/capture/planar_pose.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>

namespace slicecap::capture {
namespace {

// Reprojection of one target-plane point with the OpenCV distortion (templated for autodiff).
struct ReprojectionCost {
  Eigen::Vector2d targetMm;
  Eigen::Vector2d imagePx;
  const vision::CameraModel* camera;

  template <typename T>
  bool operator()(const T* rotation, const T* translation, T* residual) const {
    const T point[3] = {T(targetMm.x()), T(targetMm.y()), T(0.0)};
    T p[3];
    ceres::AngleAxisRotatePoint(rotation, point, p);
    p[0] += translation[0];
    p[1] += translation[1];
    p[2] += translation[2];
    const T x = p[0] / p[2];
    const T y = p[1] / p[2];
    const auto& d = camera->distortion;
    const T r2 = x * x + y * y;
    const T radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const T xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
    const T yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
    const auto& k = camera->intrinsics;
    residual[0] = k.fxPx * xd + k.cxPx - imagePx.x();
    residual[1] = k.fyPx * yd + k.cyPx - imagePx.y();
    return true;
  }
};

// Hartley normalisation: centred, mean distance sqrt(2); keeps the DLT well conditioned in mm
// and in pixels alike. nullopt when all points coincide.
std::optional<Eigen::Matrix3d> hartleyNormalisation(std::span<const Eigen::Vector2d> points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points)
    mean += p;
  mean /= static_cast<double>(points.size());
  double spread = 0.0;
  for (const auto& p : points)
    spread += (p - mean).norm();
  spread /= static_cast<double>(points.size());
  if (!(spread > 0.0)) return std::nullopt;
  const double s = std::sqrt(2.0) / spread;
  Eigen::Matrix3d t;
  t << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
  return t;
}

std::optional<vision::Pose> poseFromHomography(std::span<const PlaneCorrespondence> points,
                                               const std::vector<Eigen::Vector2d>& normalised) {
  std::vector<Eigen::Vector2d> target;
  target.reserve(points.size());
  for (const auto& p : points)
    target.push_back(p.targetMm);
  const auto fitted = fitHomography(target, normalised);
  if (!fitted) return std::nullopt;
  Eigen::Matrix3d hm = *fitted;
  const double scale = (hm.col(0).norm() + hm.col(1).norm()) / 2.0;
  if (!(scale > 0.0)) return std::nullopt;
  hm /= scale;
  if (hm(2, 2) < 0) hm = -hm;  // the target's origin lies in front of the camera
  Eigen::Matrix3d r;
  r.col(0) = hm.col(0);
  r.col(1) = hm.col(1);
  r.col(2) = hm.col(0).cross(hm.col(1));
  Eigen::JacobiSVD<Eigen::Matrix3d> rsvd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  vision::Pose pose;
  pose.rotation = rsvd.matrixU() * rsvd.matrixV().transpose();
  if (pose.rotation.determinant() < 0) return std::nullopt;
  pose.translationMm = hm.col(2);
  return pose;
}

// The other pose of the two-fold ambiguity: the normal mirrored about the line of sight.
vision::Pose mirroredPose(const vision::Pose& pose) {
  const Eigen::Vector3d sight = pose.translationMm.normalized();
  const Eigen::Vector3d normal = pose.rotation.col(2);
  const Eigen::Vector3d mirrored = 2.0 * normal.dot(sight) * sight - normal;
  vision::Pose other = pose;
  other.rotation =
      Eigen::Quaterniond::FromTwoVectors(normal, mirrored).toRotationMatrix() * pose.rotation;
  return other;
}

PoseEstimate refine(const vision::Pose& start, std::span<const PlaneCorrespondence> points,
                    const vision::CameraModel& camera) {
  double rotation[3];
  Eigen::Matrix3d r = start.rotation;
  ceres::RotationMatrixToAngleAxis(r.data(), rotation);  // Eigen is column-major, as Ceres
  double translation[3] = {start.translationMm.x(), start.translationMm.y(),
                           start.translationMm.z()};
  ceres::Problem problem;
  for (const auto& p : points)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 3, 3>(
                                 new ReprojectionCost{p.targetMm, p.imagePx, &camera}),
                             nullptr, rotation, translation);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 50;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  PoseEstimate estimate;
  ceres::AngleAxisToRotationMatrix(rotation, estimate.pose.rotation.data());
  estimate.pose.translationMm = {translation[0], translation[1], translation[2]};
  // final_cost = 1/2 sum of squared residuals over 2 per point.
  estimate.residualRmsPx =
      std::sqrt(2.0 * summary.final_cost / (2.0 * static_cast<double>(points.size())));
  return estimate;
}

}  // namespace

std::optional<Eigen::Matrix3d> fitHomography(std::span<const Eigen::Vector2d> from,
                                             std::span<const Eigen::Vector2d> to) {
  if (from.size() < 4 || from.size() != to.size()) return std::nullopt;
  const auto normaliseFrom = hartleyNormalisation(from);
  const auto normaliseTo = hartleyNormalisation(to);
  if (!normaliseFrom || !normaliseTo) return std::nullopt;
  Eigen::MatrixXd a(2 * from.size(), 9);
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector3d q = *normaliseFrom * from[i].homogeneous();
    const Eigen::Vector3d t = *normaliseTo * to[i].homogeneous();
    const double u = t.x(), v = t.y();
    a.row(2 * i) << q.x(), q.y(), 1, 0, 0, 0, -u * q.x(), -u * q.y(), -u;
    a.row(2 * i + 1) << 0, 0, 0, q.x(), q.y(), 1, -v * q.x(), -v * q.y(), -v;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d hn;
  hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  const Eigen::Matrix3d hm = normaliseTo->inverse() * hn * *normaliseFrom;
  if (!hm.allFinite() || std::abs(hm.determinant()) < 1e-300) return std::nullopt;
  return hm;
}

std::optional<PoseEstimate> estimatePlanarPose(std::span<const PlaneCorrespondence> points,
                                               const vision::CameraModel& camera) {
  if (points.size() < 4) return std::nullopt;
  std::vector<Eigen::Vector2d> normalised;
  normalised.reserve(points.size());
  for (const auto& p : points)
    normalised.push_back(camera.normalisedOf(p.imagePx));
  const auto start = poseFromHomography(points, normalised);
  if (!start) return std::nullopt;
  PoseEstimate best = refine(*start, points, camera);
  const PoseEstimate other = refine(mirroredPose(best.pose), points, camera);
  if (other.residualRmsPx < best.residualRmsPx && other.pose.translationMm.z() > 0) best = other;
  return best;
}

}  // namespace slicecap::capture
