// Planning a sweep: nominal slice geometry plus seeded hand-held imperfections.
#include "slicecap/sim/rig.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "slicecap/core/angles.hpp"

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

std::vector<FramePlan> planSweep(const SliceId& slice, double alphaDeg, const RigParams& params,
                                 const vision::CameraModel& camera,
                                 const vision::TargetGeometry& target, int bracketLevels) {
  std::string error;
  if (bracketLevels < 1 || bracketLevels > 3)
    throw std::invalid_argument("rig parameters: bracket levels must be 1..3");
  if (!params.isValid(&error)) throw std::invalid_argument("rig parameters: " + error);
  // One stream per slice, so a session's slices differ but each is reproducible on its own.
  std::mt19937_64 rng(params.seed * 1000003u +
                      static_cast<std::uint64_t>(slice.kind == SliceKind::Axial) * 7919u +
                      static_cast<std::uint64_t>(slice.elevations.thetaIDeg) * 101u +
                      static_cast<std::uint64_t>(slice.elevations.thetaVDeg));
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int n = params.framesPerSlice * bracketLevels;
  const int framesPerPair = params.alternateLed ? 2 : 1;
  std::vector<FramePlan> plans;
  double pairExposureScale = 1.0;
  for (int k = 0; k < n; ++k) {
    FramePlan plan;
    plan.index = k;
    plan.timestampUs = static_cast<std::int64_t>(std::llround(k * params.sweepSeconds * 1e6 / n));
    // An HDR bracket's LED pairs share their nominal position (consecutive frames of a camera
    // at video rate, ~1 deg apart), so every level sees each position; one level: frame k at k.
    const int pair = k / framesPerPair;
    const int position = (pair / bracketLevels) * framesPerPair + k % framesPerPair;
    plan.sliceParameterDeg = position * 360.0 / params.framesPerSlice;
    const double parameterDeg = plan.sliceParameterDeg + params.azimuthJitterDeg * normal(rng);
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
    if (uniform(rng) < params.markersOutOfViewFraction) {
      // Swing the aim away until a marker is cut by the image border while the window stays in
      // view; when the window would leave first, the frame is taken as aimed.
      const double angle = 2 * std::numbers::pi * uniform(rng);
      const Eigen::Vector3d away(std::cos(angle), std::sin(angle), 0.0);
      for (double offsetMm = 20.0; offsetMm <= 200.0; offsetMm += 5.0) {
        const vision::Pose pose = vision::lookAtPose(centre, aim + offsetMm * away, up, rollDeg);
        if (!windowInView(camera, pose, target.window)) break;
        if (!markersFullyInView(camera, pose, target)) {
          aim += offsetMm * away;
          plan.aimedOff = true;
          break;
        }
      }
    }
    plan.pose = vision::lookAtPose(centre, aim, up, rollDeg);
    plan.exposurePoses = {plan.pose};
    if (uniform(rng) < params.motionBlurFraction && params.motionBlurMaxPx > 0.0) {
      // Hand shake: the aim point slides during the exposure; image motion ~ f * slide / distance.
      const double blurPx = std::max(2.0, params.motionBlurMaxPx * (0.3 + 0.7 * uniform(rng)));
      const double slideMm = blurPx * distanceMm / camera.intrinsics.fxPx;
      const double angle = 2 * std::numbers::pi * uniform(rng);
      const Eigen::Vector3d slide(slideMm * std::cos(angle), slideMm * std::sin(angle), 0.0);
      const int steps = std::clamp(static_cast<int>(std::ceil(blurPx / 1.5)), 2, 8);
      plan.exposurePoses.clear();
      for (int s = 0; s < steps; ++s)
        plan.exposurePoses.push_back(
            vision::lookAtPose(centre, aim + slide * ((s + 0.5) / steps - 0.5), up, rollDeg));
    }
    const double lightThetaDeg = slice.elevations.thetaIDeg + params.lightElevationErrorDeg;
    plan.lightMm = params.lightDistanceMm * directionVector(lightThetaDeg, phiIDeg);
    plan.ledOn = !params.alternateLed || k % 2 == 0;
    // LED on/off pairs share their exposure, so the off frame measures the on frame's ambient.
    if (plan.ledOn || !params.alternateLed)
      pairExposureScale =
          uniform(rng) < params.exposureChangeFraction ? 0.5 + 0.4 * uniform(rng) : 1.0;
    plan.exposureScale = pairExposureScale;
    plan.gain = params.gain;
    if (uniform(rng) < params.occlusionFraction) {
      // The arm: a bar from outside the image to just past the window centre.
      if (const auto c = camera.project(plan.pose.toCamera(Eigen::Vector3d::Zero()))) {
        const double angle = 2 * std::numbers::pi * uniform(rng);
        const Eigen::Vector2d along(std::cos(angle), std::sin(angle)),
            across(-along.y(), along.x());
        const double halfWidthPx = 25.0, reachPx = 3000.0;
        const Eigen::Vector2d tip = *c - along * 20.0;
        plan.occluder = Occluder{{tip - across * halfWidthPx, tip + across * halfWidthPx,
                                  tip + along * reachPx + across * halfWidthPx,
                                  tip + along * reachPx - across * halfWidthPx}};
      }
    }
    plans.push_back(plan);
  }
  return plans;
}

}  // namespace slicecap::sim
