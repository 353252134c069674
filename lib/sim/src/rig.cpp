// Planning a sweep: nominal slice geometry plus seeded hand-held imperfections.
#include "slicecap/sim/rig.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "slicecap/core/angles.hpp"
#include "slicecap/sim/sim_error.hpp"

namespace slicecap::sim {
namespace {

Eigen::Vector3d directionVector(double thetaDeg, double phiDeg) {
  const UnitVector v = toUnitVector({thetaDeg, phiDeg});
  return {v.x, v.y, v.z};
}

bool fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

bool inImage(const vision::CameraModel& camera, const vision::Pose& pose,
             const vision::PointMm& p) {
  const auto px = camera.project(pose.toCamera({p.xMm, p.yMm, 0.0}));
  return px && px->x() >= 0 && px->y() >= 0 && px->x() <= camera.intrinsics.widthPx - 1 &&
         px->y() <= camera.intrinsics.heightPx - 1;
}

// True when every marker corner is in the image.
bool markersFullyInView(const vision::CameraModel& camera, const vision::Pose& pose,
                        const vision::TargetGeometry& target) {
  for (const vision::Marker& m : target.markers) {
    for (const vision::PointMm& c : m.cornersMm) {
      if (!inImage(camera, pose, c)) return false;
    }
  }
  return true;
}

// True when the whole window is in the image.
bool windowInView(const vision::CameraModel& camera, const vision::Pose& pose,
                  const vision::RectMm& window) {
  for (double x : {window.xMinMm, window.xMaxMm}) {
    for (double y : {window.yMinMm, window.yMaxMm}) {
      if (!inImage(camera, pose, {x, y})) return false;
    }
  }
  return true;
}

// The sweep's random stream and its two distributions (the normal one keeps state between draws).
struct SweepDraws {
  std::mt19937_64 rng;
  std::normal_distribution<double> normal{0.0, 1.0};
  std::uniform_real_distribution<double> uniform{0.0, 1.0};
};

// One stream per slice, so a session's slices differ but each is reproducible on its own.
SweepDraws sweepDraws(const SliceId& slice, const RigParams& params) {
  return SweepDraws{std::mt19937_64(
      params.seed * 1000003u + static_cast<std::uint64_t>(slice.kind == SliceKind::Axial) * 7919u +
      static_cast<std::uint64_t>(slice.elevations.thetaIDeg) * 101u +
      static_cast<std::uint64_t>(slice.elevations.thetaVDeg))};
}

// Where the hand holds the camera for one frame: the light's azimuth, the camera's centre, up
// direction, roll and aim point.
struct Viewpoint {
  double phiIDeg, distanceMm, rollDeg;
  Eigen::Vector3d centre, up, aim;
};

Viewpoint drawViewpoint(const SliceId& slice, double alphaDeg, const RigParams& params,
                        double sliceParameterDeg, SweepDraws& d) {
  std::mt19937_64& rng = d.rng;
  std::normal_distribution<double>& normal = d.normal;
  const double parameterDeg = sliceParameterDeg + params.azimuthJitterDeg * normal(rng);
  const bool axial = slice.kind == SliceKind::Axial;
  const double phiIDeg = wrapDeg360(axial ? parameterDeg : 360.0 - parameterDeg);
  const double phiVDeg = wrapDeg360(axial ? parameterDeg + alphaDeg : parameterDeg);
  const double thetaVDeg =
      std::clamp(slice.elevations.thetaVDeg + params.elevationJitterDeg * normal(rng), 1.0, 85.0);
  const double distanceMm =
      std::max(100.0, params.cameraDistanceMm + params.distanceJitterMm * normal(rng));
  const Eigen::Vector3d centre = distanceMm * directionVector(thetaVDeg, phiVDeg);
  const Eigen::Vector3d up(-std::cos(degToRad(phiVDeg)), -std::sin(degToRad(phiVDeg)), 0.0);
  const double rollDeg = params.rollJitterDeg * normal(rng);
  Eigen::Vector3d aim(params.aimJitterMm * normal(rng), params.aimJitterMm * normal(rng), 0.0);
  return {phiIDeg, distanceMm, rollDeg, centre, up, aim};
}

// Swing the aim away until a marker is cut by the image border while the window stays in
// view; when the window would leave first, the frame is taken as aimed.
void aimOffMarkers(const vision::CameraModel& camera, const vision::TargetGeometry& target,
                   Viewpoint& view, FramePlan& plan, SweepDraws& d) {
  const double angle = 2 * std::numbers::pi * d.uniform(d.rng);
  const Eigen::Vector3d away(std::cos(angle), std::sin(angle), 0.0);
  for (double offsetMm = 20.0; offsetMm <= 200.0; offsetMm += 5.0) {
    const vision::Pose pose =
        vision::lookAtPose(view.centre, view.aim + offsetMm * away, view.up, view.rollDeg);
    if (!windowInView(camera, pose, target.window)) break;
    if (!markersFullyInView(camera, pose, target)) {
      view.aim += offsetMm * away;
      plan.aimedOff = true;
      break;
    }
  }
}

// Hand shake: the aim point slides during the exposure; image motion ~ f * slide / distance.
std::vector<vision::Pose> blurredPoses(const RigParams& params, const vision::CameraModel& camera,
                                       const Viewpoint& view, SweepDraws& d) {
  std::mt19937_64& rng = d.rng;
  std::uniform_real_distribution<double>& uniform = d.uniform;
  const double blurPx = std::max(2.0, params.motionBlurMaxPx * (0.3 + 0.7 * uniform(rng)));
  const double slideMm = blurPx * view.distanceMm / camera.intrinsics.fxPx;
  const double angle = 2 * std::numbers::pi * uniform(rng);
  const Eigen::Vector3d slide(slideMm * std::cos(angle), slideMm * std::sin(angle), 0.0);
  const int steps = std::clamp(static_cast<int>(std::ceil(blurPx / 1.5)), 2, 8);
  std::vector<vision::Pose> poses;
  for (int s = 0; s < steps; ++s)
    poses.push_back(vision::lookAtPose(view.centre, view.aim + slide * ((s + 0.5) / steps - 0.5),
                                       view.up, view.rollDeg));
  return poses;
}

// The arm: a bar from outside the image to just past the window centre (none when the centre
// does not project).
std::optional<Occluder> armOccluder(const vision::CameraModel& camera, const vision::Pose& pose,
                                    SweepDraws& d) {
  const auto c = camera.project(pose.toCamera(Eigen::Vector3d::Zero()));
  if (!c) return std::nullopt;
  const double angle = 2 * std::numbers::pi * d.uniform(d.rng);
  const Eigen::Vector2d along(std::cos(angle), std::sin(angle)), across(-along.y(), along.x());
  const double halfWidthPx = 25.0, reachPx = 3000.0;
  const Eigen::Vector2d tip = *c - along * 20.0;
  return Occluder{{tip - across * halfWidthPx, tip + across * halfWidthPx,
                   tip + along * reachPx + across * halfWidthPx,
                   tip + along * reachPx - across * halfWidthPx}};
}

}  // namespace

RigParams RigParams::ideal() {
  return RigParams{};
}

RigParams RigParams::realistic() {
  RigParams p;
  p.elevationJitterDeg = 1.5;
  p.azimuthJitterDeg = 2.0;
  p.distanceJitterMm = 15.0;
  p.aimJitterMm = 6.0;
  p.rollJitterDeg = 8.0;
  p.lightElevationErrorDeg = 0.7;
  p.motionBlurFraction = 0.1;
  p.motionBlurMaxPx = 10.0;
  p.readNoise = 0.002;
  p.fullWellElectrons = 8000.0;
  p.exposureChangeFraction = 0.15;
  p.occlusionFraction = 0.05;
  p.markersOutOfViewFraction = 0.05;
  return p;
}

RigParams RigParams::steady() {
  const RigParams noisy = realistic();
  RigParams p;
  p.readNoise = noisy.readNoise;
  p.fullWellElectrons = noisy.fullWellElectrons;
  return p;
}

bool RigParams::isValid(std::string* error) const {
  if (framesPerSlice < 2 || framesPerSlice > 10000)
    return fail(error, "frames per slice must be 2..10000");
  const std::pair<const char*, double> positive[] = {
      {"sweep seconds", sweepSeconds},     {"camera distance", cameraDistanceMm},
      {"light distance", lightDistanceMm}, {"LED intensity", ledIntensityWPerSr},
      {"sensor response", sensorResponse}, {"gain", gain}};
  for (const auto& [name, value] : positive) {
    if (!(std::isfinite(value) && value > 0.0))
      return fail(error, std::string(name) + " must be positive");
  }
  if (cameraDistanceMm < 100.0 || lightDistanceMm < 100.0)
    return fail(error, "camera and light distances must be at least 100 mm");
  if (maxExposureLevels < 1 || maxExposureLevels > 3)
    return fail(error, "exposure levels must be 1..3");
  if (exposureUs && !(*exposureUs > 0.0 && std::isfinite(*exposureUs)))
    return fail(error, "exposure must be positive");
  const std::pair<const char*, double> nonNegative[] = {{"ambient irradiance", ambientIrradiance},
                                                        {"elevation jitter", elevationJitterDeg},
                                                        {"azimuth jitter", azimuthJitterDeg},
                                                        {"distance jitter", distanceJitterMm},
                                                        {"aim jitter", aimJitterMm},
                                                        {"roll jitter", rollJitterDeg},
                                                        {"motion blur length", motionBlurMaxPx},
                                                        {"read noise", readNoise},
                                                        {"full well", fullWellElectrons}};
  for (const auto& [name, value] : nonNegative) {
    if (!(std::isfinite(value) && value >= 0.0))
      return fail(error, std::string(name) + " must be >= 0");
  }
  if (!(deskAlbedo >= 0.0 && deskAlbedo <= 1.0))
    return fail(error, "desk albedo must be in [0, 1]");
  if (!std::isfinite(lightElevationErrorDeg) || std::abs(lightElevationErrorDeg) > 10.0)
    return fail(error, "light elevation error must be within 10 deg");
  const std::pair<const char*, double> fractions[] = {
      {"motion blur fraction", motionBlurFraction},
      {"exposure change fraction", exposureChangeFraction},
      {"occlusion fraction", occlusionFraction},
      {"out-of-view fraction", markersOutOfViewFraction}};
  for (const auto& [name, value] : fractions) {
    if (!(value >= 0.0 && value <= 1.0))
      return fail(error, std::string(name) + " must be in [0, 1]");
  }
  return true;
}

namespace {

// Frame k of n: its nominal and jittered camera, light, LED, exposure and imperfections, drawn
// from `d` in the order of the frames. pairExposureScale carries an LED pair's exposure.
FramePlan planFrame(int k, int n, const SliceId& slice, double alphaDeg, const RigParams& params,
                    const vision::CameraModel& camera, const vision::TargetGeometry& target,
                    int bracketLevels, SweepDraws& d, double& pairExposureScale) {
  const int framesPerPair = params.alternateLed ? 2 : 1;
  FramePlan plan;
  plan.index = k;
  plan.timestampUs = static_cast<std::int64_t>(std::llround(k * params.sweepSeconds * 1e6 / n));
  // An HDR bracket's LED pairs share their nominal position (consecutive frames of a camera
  // at video rate, ~1 deg apart), so every level sees each position; one level: frame k at k.
  const int pair = k / framesPerPair;
  const int position = (pair / bracketLevels) * framesPerPair + k % framesPerPair;
  plan.sliceParameterDeg = position * 360.0 / params.framesPerSlice;
  Viewpoint view = drawViewpoint(slice, alphaDeg, params, plan.sliceParameterDeg, d);
  if (d.uniform(d.rng) < params.markersOutOfViewFraction)
    aimOffMarkers(camera, target, view, plan, d);
  plan.pose = vision::lookAtPose(view.centre, view.aim, view.up, view.rollDeg);
  plan.exposurePoses = {plan.pose};
  if (d.uniform(d.rng) < params.motionBlurFraction && params.motionBlurMaxPx > 0.0)
    plan.exposurePoses = blurredPoses(params, camera, view, d);
  const double lightThetaDeg = slice.elevations.thetaIDeg + params.lightElevationErrorDeg;
  plan.lightMm = params.lightDistanceMm * directionVector(lightThetaDeg, view.phiIDeg);
  plan.ledOn = !params.alternateLed || k % 2 == 0;
  // LED on/off pairs share their exposure, so the off frame measures the on frame's ambient.
  if (plan.ledOn || !params.alternateLed)
    pairExposureScale =
        d.uniform(d.rng) < params.exposureChangeFraction ? 0.5 + 0.4 * d.uniform(d.rng) : 1.0;
  plan.exposureScale = pairExposureScale;
  plan.gain = params.gain;
  if (d.uniform(d.rng) < params.occlusionFraction)
    plan.occluder = armOccluder(camera, plan.pose, d);
  return plan;
}

}  // namespace

std::vector<FramePlan> planSweep(const SliceId& slice, double alphaDeg, const RigParams& params,
                                 const vision::CameraModel& camera,
                                 const vision::TargetGeometry& target, int bracketLevels) {
  std::string error;
  if (bracketLevels < 1 || bracketLevels > 3)
    throw SimError("rig parameters: bracket levels must be 1..3");
  if (!params.isValid(&error)) throw SimError("rig parameters: " + error);
  SweepDraws draws = sweepDraws(slice, params);
  const int n = params.framesPerSlice * bracketLevels;
  std::vector<FramePlan> plans;
  double pairExposureScale = 1.0;
  for (int k = 0; k < n; ++k)
    plans.push_back(planFrame(k, n, slice, alphaDeg, params, camera, target, bracketLevels, draws,
                              pairExposureScale));
  return plans;
}

}  // namespace slicecap::sim
