// Camera calibration: Zhang's closed form from per-view homographies, then a Ceres bundle
// adjustment of intrinsics, distortion and poses.
#include "slicecap/capture/camera_calibration.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <memory>

namespace slicecap::capture {
namespace {

// Reprojection of a target-plane point through the full camera (templated for autodiff):
// intrinsics (fx, fy, cx, cy), distortion (k1, k2, p1, p2, k3), pose (angle-axis, translation).
struct CalibrationCost {
  Eigen::Vector2d targetMm;
  Eigen::Vector2d imagePx;

  template <typename T>
  bool operator()(const T* k, const T* d, const T* rotation, const T* translation,
                  T* residual) const {
    const T point[3] = {T(targetMm.x()), T(targetMm.y()), T(0.0)};
    T p[3];
    ceres::AngleAxisRotatePoint(rotation, point, p);
    const T z = p[2] + translation[2];
    const T x = (p[0] + translation[0]) / z;
    const T y = (p[1] + translation[1]) / z;
    const T r2 = x * x + y * y;
    const T radial = 1.0 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
    const T xd = x * radial + 2.0 * d[2] * x * y + d[3] * (r2 + 2.0 * x * x);
    const T yd = y * radial + d[2] * (r2 + 2.0 * y * y) + 2.0 * d[3] * x * y;
    residual[0] = k[0] * xd + k[2] - imagePx.x();
    residual[1] = k[1] * yd + k[3] - imagePx.y();
    return true;
  }

  static ceres::CostFunction* Create(const PlaneCorrespondence& p) {
    return new ceres::AutoDiffCostFunction<CalibrationCost, 2, 4, 5, 3, 3>(
        new CalibrationCost{p.targetMm, p.imagePx});
  }
};

// Zhang's constraint row v_ij of the image of the absolute conic b = (B11, B22, B13, B23, B33)
// (zero skew: B12 = 0).
Eigen::Matrix<double, 1, 5> conicRow(const Eigen::Matrix3d& h, int i, int j) {
  Eigen::Matrix<double, 1, 5> v;
  v << h(0, i) * h(0, j), h(1, i) * h(1, j), h(2, i) * h(0, j) + h(0, i) * h(2, j),
      h(2, i) * h(1, j) + h(1, i) * h(2, j), h(2, i) * h(2, j);
  return v;
}

// Zhang's closed-form intrinsics (zero skew) from homographies target mm -> pixels. The pixels
// are first scaled to about [-1, 1] so the conic's entries are of one magnitude.
std::optional<vision::CameraIntrinsics> closedFormIntrinsics(
    const std::vector<Eigen::Matrix3d>& homographies, int widthPx, int heightPx) {
  const double scale = 2.0 / std::max(widthPx, heightPx);
  Eigen::Matrix3d toUnit;
  toUnit << scale, 0, -scale * widthPx / 2.0, 0, scale, -scale * heightPx / 2.0, 0, 0, 1;
  Eigen::MatrixXd v(2 * homographies.size(), 5);
  for (std::size_t n = 0; n < homographies.size(); ++n) {
    Eigen::Matrix3d h = toUnit * homographies[n];
    h /= h.norm();
    v.row(2 * n) = conicRow(h, 0, 1);
    v.row(2 * n + 1) = conicRow(h, 0, 0) - conicRow(h, 1, 1);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(v, Eigen::ComputeFullV);
  Eigen::Matrix<double, 5, 1> b = svd.matrixV().col(4);
  if (b(0) < 0) b = -b;
  const double b11 = b(0), b22 = b(1), b13 = b(2), b23 = b(3), b33 = b(4);
  if (!(b11 > 0) || !(b22 > 0)) return std::nullopt;
  const double v0 = -b23 / b22;
  const double lambda = b33 - b13 * b13 / b11 + v0 * b23;
  if (!(lambda > 0)) return std::nullopt;
  const double alpha = std::sqrt(lambda / b11), beta = std::sqrt(lambda / b22);
  const double u0 = -b13 * alpha * alpha / lambda;
  vision::CameraIntrinsics k;
  k.widthPx = widthPx;
  k.heightPx = heightPx;
  k.fxPx = alpha / scale;
  k.fyPx = beta / scale;
  k.cxPx = u0 / scale + widthPx / 2.0;
  k.cyPx = v0 / scale + heightPx / 2.0;
  if (!std::isfinite(k.fxPx) || !std::isfinite(k.fyPx) || !std::isfinite(k.cxPx) ||
      !std::isfinite(k.cyPx))
    return std::nullopt;
  return k;
}

double tiltDeg(const vision::Pose& pose) {
  return std::acos(std::min(1.0, std::abs(pose.rotation(2, 2)))) * 180.0 / M_PI;
}

std::vector<const CalibrationView*> selectViews(const std::vector<CalibrationView>& views,
                                                const CalibrationSettings& settings) {
  std::vector<const CalibrationView*> usable;
  for (const auto& view : views)
    if (static_cast<int>(view.points.size()) >= settings.minPointsPerView) usable.push_back(&view);
  if (static_cast<int>(usable.size()) <= settings.maxViews) return usable;
  // Evenly spread over the input order: the sweeps' frames go around the target.
  std::vector<const CalibrationView*> spread;
  for (int i = 0; i < settings.maxViews; ++i)
    spread.push_back(usable[static_cast<std::size_t>(i) * usable.size() / settings.maxViews]);
  return spread;
}

struct PoseBlock {
  double rotation[3];
  double translation[3];
};

// One standard deviation of the nine camera parameters: (J^T J)^-1 scaled by the residual
// variance, from the Jacobian at the solution. Zeros when the normal matrix is singular.
// The distortion coefficients in `fixed` have no column (Ceres's tangent space) and sigma 0.
std::array<double, 9> cameraSigma(ceres::Problem& problem, const std::vector<double*>& blocks,
                                  const std::vector<int>& fixed, double sumSquares,
                                  int residualCount) {
  std::array<double, 9> sigma{};
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = blocks;
  options.apply_loss_function = false;
  ceres::CRSMatrix crs;
  if (!problem.Evaluate(options, nullptr, nullptr, nullptr, &crs)) return sigma;
  std::vector<Eigen::Triplet<double>> entries;
  for (int row = 0; row < crs.num_rows; ++row)
    for (int at = crs.rows[row]; at < crs.rows[row + 1]; ++at)
      entries.emplace_back(row, crs.cols[at], crs.values[at]);
  Eigen::SparseMatrix<double> jacobian(crs.num_rows, crs.num_cols);
  jacobian.setFromTriplets(entries.begin(), entries.end());
  const Eigen::MatrixXd normal = Eigen::MatrixXd(jacobian.transpose() * jacobian);
  const int freedom = residualCount - crs.num_cols;
  if (freedom <= 0) return sigma;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
  if (!lu.isInvertible()) return sigma;
  const Eigen::MatrixXd covariance = lu.inverse() * (sumSquares / freedom);
  int column = 0;
  for (int i = 0; i < 9; ++i) {
    if (i >= 4 && std::find(fixed.begin(), fixed.end(), i - 4) != fixed.end()) continue;
    sigma[i] = std::sqrt(std::max(0.0, covariance(column, column)));
    ++column;
  }
  return sigma;
}

// One homography target mm -> pixels per view; throws CalibrationError naming a degenerate view.
std::vector<Eigen::Matrix3d> viewHomographies(const std::vector<const CalibrationView*>& used) {
  std::vector<Eigen::Matrix3d> homographies;
  for (const CalibrationView* view : used) {
    std::vector<Eigen::Vector2d> from, to;
    for (const auto& p : view->points) {
      from.push_back(p.targetMm);
      to.push_back(p.imagePx);
    }
    const auto h = fitHomography(from, to);
    if (!h) throw CalibrationError("calibration: " + view->source + ": degenerate marker corners");
    homographies.push_back(*h);
  }
  return homographies;
}

// Each view's pose under the closed-form camera, as Ceres blocks; sets result.maxTiltDeg. Throws
// CalibrationError for a view without a pose, or when every view is nearly fronto-parallel.
std::vector<PoseBlock> initialPoses(const std::vector<const CalibrationView*>& used,
                                    const vision::CameraModel& camera,
                                    const CalibrationSettings& settings,
                                    CameraCalibration& result) {
  std::vector<PoseBlock> poses(used.size());
  for (std::size_t n = 0; n < used.size(); ++n) {
    const auto estimate = estimatePlanarPose(used[n]->points, camera);
    if (!estimate) throw CalibrationError("calibration: " + used[n]->source + ": no pose");
    Eigen::Matrix3d r = estimate->pose.rotation;
    ceres::RotationMatrixToAngleAxis(r.data(), poses[n].rotation);
    for (int i = 0; i < 3; ++i)
      poses[n].translation[i] = estimate->pose.translationMm[i];
    result.maxTiltDeg = std::max(result.maxTiltDeg, tiltDeg(estimate->pose));
  }
  if (result.maxTiltDeg < settings.minTiltDeg)
    throw CalibrationError("calibration: every view is nearly fronto-parallel (most oblique " +
                           std::to_string(result.maxTiltDeg) +
                           " deg): the focal length is not observable; record the target tilted "
                           "20 deg or more, from several directions");
  return poses;
}

// The target covers the middle of the image only: the high-order radial terms are free to
// fold the lens outside it. Fix k3 (then k2 too) at zero unless the corners reach out to most
// of the image's radius, and take the first ladder step whose camera is valid.
std::vector<std::vector<int>> distortionLadder(const std::vector<const CalibrationView*>& used,
                                               const vision::CameraIntrinsics& initial, int widthPx,
                                               int heightPx) {
  double reach = 0.0;
  for (const CalibrationView* view : used)
    for (const auto& p : view->points)
      reach = std::max(reach, ((p.imagePx - Eigen::Vector2d(initial.cxPx, initial.cyPx))
                                   .cwiseQuotient(Eigen::Vector2d(initial.fxPx, initial.fyPx)))
                                  .norm());
  const double cornerRadius =
      Eigen::Vector2d(widthPx / 2.0 / initial.fxPx, heightPx / 2.0 / initial.fyPx).norm();
  std::vector<std::vector<int>> ladder = {{4}, {1, 4}};
  if (reach >= 0.8 * cornerRadius) ladder.insert(ladder.begin(), std::vector<int>{});
  return ladder;
}

// The parameter blocks Ceres adjusts in place; the problem points into them, so this stays put.
struct BundleState {
  double k[4], d[5];
  std::vector<PoseBlock> poses;
  std::unique_ptr<ceres::Problem> problem;
  int residualCount = 0;
};

// One ladder step: the adjustment from the closed form with the distortion terms `fixed` at zero.
// Throws CalibrationError when Ceres has no usable solution.
void adjustBundle(const std::vector<const CalibrationView*>& used,
                  const vision::CameraIntrinsics& initial, const std::vector<PoseBlock>& startPoses,
                  const std::vector<int>& fixed, const CalibrationSettings& settings,
                  BundleState& state) {
  double* k = state.k;
  double* d = state.d;
  k[0] = initial.fxPx, k[1] = initial.fyPx, k[2] = initial.cxPx, k[3] = initial.cyPx;
  std::fill(d, d + 5, 0.0);
  state.poses = startPoses;
  state.problem = std::make_unique<ceres::Problem>();
  state.residualCount = 0;
  for (std::size_t n = 0; n < used.size(); ++n)
    for (const auto& p : used[n]->points) {
      state.problem->AddResidualBlock(CalibrationCost::Create(p),
                                      new ceres::HuberLoss(settings.robustLossPx), k, d,
                                      state.poses[n].rotation, state.poses[n].translation);
      state.residualCount += 2;
    }
  if (!fixed.empty()) state.problem->SetManifold(d, new ceres::SubsetManifold(5, fixed));
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = 200;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, state.problem.get(), &summary);
  if (!summary.IsSolutionUsable())
    throw CalibrationError("calibration: the bundle adjustment failed: " + summary.message);
}

// The first ladder step whose camera is valid, into `camera` and result.fixedDistortion; throws
// CalibrationError when none is.
void adjustAlongLadder(const std::vector<const CalibrationView*>& used,
                       const vision::CameraIntrinsics& initial,
                       const std::vector<std::vector<int>>& ladder, int widthPx, int heightPx,
                       const CalibrationSettings& settings, BundleState& state,
                       vision::CameraModel& camera, CameraCalibration& result) {
  const std::vector<PoseBlock> startPoses = state.poses;
  std::string problemText;
  for (std::size_t step = 0; step < ladder.size(); ++step) {
    const std::vector<int>& fixed = ladder[step];
    adjustBundle(used, initial, startPoses, fixed, settings, state);
    const double* k = state.k;
    const double* d = state.d;
    camera.intrinsics = {widthPx, heightPx, k[0], k[1], k[2], k[3]};
    camera.distortion = {d[0], d[1], d[2], d[3], d[4]};
    if (camera.isValid(&problemText)) {
      result.fixedDistortion = fixed;
      break;
    }
    if (step + 1 == ladder.size())
      throw CalibrationError("calibration: the solution is not a valid camera (" + problemText +
                             "); record more views, with the target near the image corners too");
  }
}

// Per-view and total RMS reprojection error of the adjusted camera and poses, with the views'
// sources and point count; returns the sum of squares.
double measureReprojection(const std::vector<const CalibrationView*>& used,
                           const std::vector<PoseBlock>& poses, const vision::CameraModel& camera,
                           CameraCalibration& result) {
  double sumSquares = 0.0;
  for (std::size_t n = 0; n < used.size(); ++n) {
    vision::Pose pose;
    ceres::AngleAxisToRotationMatrix(poses[n].rotation, pose.rotation.data());
    pose.translationMm = {poses[n].translation[0], poses[n].translation[1],
                          poses[n].translation[2]};
    double viewSquares = 0.0;
    for (const auto& p : used[n]->points) {
      const auto projected = camera.project(pose.toCamera({p.targetMm.x(), p.targetMm.y(), 0}));
      viewSquares += projected ? (*projected - p.imagePx).squaredNorm() : 1e6;
    }
    sumSquares += viewSquares;
    result.viewRmsPx.push_back(std::sqrt(viewSquares / used[n]->points.size()));
    result.usedSources.push_back(used[n]->source);
    result.pointsUsed += static_cast<int>(used[n]->points.size());
  }
  return sumSquares;
}

// Closed form, poses, bundle adjustment over the views `used` (already selected).
CameraCalibration calibrateViews(const std::vector<const CalibrationView*>& used, int widthPx,
                                 int heightPx, const CalibrationSettings& settings) {
  const std::vector<Eigen::Matrix3d> homographies = viewHomographies(used);
  const auto initial = closedFormIntrinsics(homographies, widthPx, heightPx);
  if (!initial)
    throw CalibrationError(
        "calibration: the views are degenerate (nearly fronto-parallel, or all turned the same "
        "way): the focal length is not observable; record the target from several elevations "
        "and azimuths, tilted 20 deg or more");

  vision::CameraModel camera;
  camera.intrinsics = *initial;
  CameraCalibration result;
  BundleState state;
  state.poses = initialPoses(used, camera, settings, result);
  const std::vector<std::vector<int>> ladder = distortionLadder(used, *initial, widthPx, heightPx);
  adjustAlongLadder(used, *initial, ladder, widthPx, heightPx, settings, state, camera, result);

  const double sumSquares = measureReprojection(used, state.poses, camera, result);
  result.camera = camera;
  result.viewsUsed = static_cast<int>(used.size());
  result.rmsReprojectionPx = std::sqrt(sumSquares / result.pointsUsed);
  std::vector<double*> blocks = {state.k, state.d};
  for (auto& pose : state.poses) {
    blocks.push_back(pose.rotation);
    blocks.push_back(pose.translation);
  }
  result.sigma =
      cameraSigma(*state.problem, blocks, result.fixedDistortion, sumSquares, state.residualCount);
  return result;
}

}  // namespace

CameraCalibration calibrateCamera(const std::vector<CalibrationView>& views, int widthPx,
                                  int heightPx, const CalibrationSettings& settings) {
  if (widthPx <= 0 || heightPx <= 0)
    throw CalibrationError("calibration: image size " + std::to_string(widthPx) + " x " +
                           std::to_string(heightPx) + " is not positive");
  std::vector<const CalibrationView*> used = selectViews(views, settings);
  if (static_cast<int>(used.size()) < settings.minViews)
    throw CalibrationError("calibration: " + std::to_string(used.size()) + " of " +
                           std::to_string(views.size()) + " frames show at least " +
                           std::to_string(settings.minPointsPerView) + " marker corners; need " +
                           std::to_string(settings.minViews) +
                           " (record the whole target, from several elevations)");
  CameraCalibration result = calibrateViews(used, widthPx, heightPx, settings);
  // Motion-blurred frames' corners are off by a pixel or more along the motion; the Huber loss
  // limits their pull, dropping them and fitting again removes it.
  std::vector<double> sorted = result.viewRmsPx;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double limit = settings.outlierViewFactor * sorted[sorted.size() / 2];
  std::vector<const CalibrationView*> kept;
  std::vector<std::string> dropped;
  for (std::size_t n = 0; n < used.size(); ++n) {
    if (result.viewRmsPx[n] <= limit)
      kept.push_back(used[n]);
    else
      dropped.push_back(used[n]->source);
  }
  if (dropped.empty() || static_cast<int>(kept.size()) < settings.minViews) return result;
  result = calibrateViews(kept, widthPx, heightPx, settings);
  result.droppedSources = dropped;
  return result;
}

}  // namespace slicecap::capture
