// Rendering sweeps to recordings and truth files.
#include "slicecap/sim/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slicecap/core/version.hpp"

namespace slicecap::sim {
namespace {

FrameScene sceneOf(const FramePlan& plan, std::uint64_t noiseSeed) {
  return {plan.exposurePoses, plan.lightMm,  plan.ledOn, plan.exposureUs,
          plan.gain,          plan.occluder, noiseSeed};
}

bool inImage(const vision::CameraModel& camera, const std::optional<Eigen::Vector2d>& px) {
  return px && px->x() >= 0.0 && px->y() >= 0.0 && px->x() <= camera.intrinsics.widthPx - 1.0 &&
         px->y() <= camera.intrinsics.heightPx - 1.0;
}

FrameTruth truthOf(const FrameRenderer& renderer, const FramePlan& plan, const FrameScene& scene) {
  const vision::CameraModel& camera = renderer.camera();
  FrameTruth t;
  t.timestampUs = plan.timestampUs;
  t.ledOn = plan.ledOn;
  t.exposureUs = plan.exposureUs;
  t.gain = plan.gain;
  t.sliceParameterDeg = plan.sliceParameterDeg;
  t.pose = plan.pose;
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  t.view = vision::directionFrom(centre, plan.pose.cameraCentreMm());
  t.cameraDistanceMm = plan.pose.cameraCentreMm().norm();
  t.lightMm = plan.lightMm;
  t.light = vision::directionFrom(centre, plan.lightMm);
  FrameScene sharp = scene;
  sharp.exposurePoses = {plan.pose};
  const PointRadiometry r = renderer.windowPoint(sharp, centre);
  t.ledIrradiance = r.ledIrradiance;
  t.brdf = r.brdf;
  t.expectedLinear = r.expectedLinear;
  const auto first = camera.project(plan.exposurePoses.front().toCamera(centre));
  const auto last = camera.project(plan.exposurePoses.back().toCamera(centre));
  if (first && last) t.motionBlurPx = (*first - *last).norm();
  t.occluded = plan.occluder.has_value();
  t.aimedOff = plan.aimedOff;
  for (const vision::Marker& m : renderer.target().markers) {
    bool visible = true;
    for (const vision::PointMm& c : m.cornersMm) {
      const auto px = camera.project(plan.pose.toCamera({c.xMm, c.yMm, 0.0}));
      visible = visible && inImage(camera, px);
      if (visible && plan.occluder) {
        // Inside the arm's quad (its corners run around it): hidden.
        bool positive = false, negative = false;
        for (int i = 0; i < 4; ++i) {
          const Eigen::Vector2d& a = plan.occluder->cornersPx[i];
          const Eigen::Vector2d& b = plan.occluder->cornersPx[(i + 1) % 4];
          const double cross = (b - a).x() * (px->y() - a.y()) - (b - a).y() * (px->x() - a.x());
          positive |= cross > 0, negative |= cross < 0;
        }
        visible = positive && negative;
      }
    }
    if (visible) t.markersInView.push_back(m.id);
  }
  return t;
}

}  // namespace

MeteredRadiance meterSweep(const FrameRenderer& renderer, const RigParams& rig,
                           const std::vector<FramePlan>& plans) {
  MeteredRadiance metered;
  const vision::TargetGeometry& target = renderer.target();
  for (const FramePlan& plan : plans) {
    FrameScene scene = sceneOf(plan, 0);
    scene.ledOn = true;
    scene.exposureUs = 1e6;
    scene.gain = 1.0;
    const double perRadiance = renderer.pixelScale(scene);
    metered.window = std::max(
        metered.window,
        renderer.windowPoint(scene, Eigen::Vector3d::Zero()).expectedLinear.maxChannel() /
            perRadiance);
    // The sample square on a 9 x 9 grid: a cell clipped in every frame of a bin is only a lower
    // bound in the HDR merge.
    const vision::RectMm& w = target.window;
    const double half = kMeteredSquareFraction * std::min(w.widthMm(), w.heightMm()) / 2.0;
    constexpr int kSteps = 8;
    for (int j = 0; j <= kSteps; ++j)
      for (int i = 0; i <= kSteps; ++i) {
        const Eigen::Vector3d at(w.centre().xMm + half * (2.0 * i / kSteps - 1.0),
                                 w.centre().yMm + half * (2.0 * j / kSteps - 1.0), 0.0);
        metered.windowSquare =
            std::max(metered.windowSquare,
                     renderer.windowPoint(scene, at).expectedLinear.maxChannel() / perRadiance);
      }
    for (const vision::Patch& p : target.patches) {
      if (p.kind != vision::PatchKind::White) continue;
      const Eigen::Vector3d at(p.rect.centre().xMm, p.rect.centre().yMm, 0.0);
      metered.references =
          std::max(metered.references, p.albedo.maxChannel() / std::numbers::pi *
                                           (renderer.ledIrradiance(scene, at) + rig.ambientIrradiance));
    }
  }
  return metered;
}

namespace {

// The exposure (us, 20 us .. 0.5 s) that puts `radiance` (W / (m^2 sr)) at 80 % of full scale.
double exposureForUs(const RigParams& rig, double radiance) {
  const double exposureS = 0.8 / (rig.sensorResponse * rig.gain * std::max(radiance, 1e-12));
  return std::clamp(exposureS * 1e6, 20.0, 5e5);
}

}  // namespace

double chooseExposureUs(const FrameRenderer& renderer, const RigParams& rig,
                        const std::vector<FramePlan>& plans) {
  const MeteredRadiance metered = meterSweep(renderer, rig, plans);
  return exposureForUs(rig, rig.metering == RigParams::Metering::Paper
                                ? metered.references
                                : std::max(metered.window, metered.references));
}

std::vector<double> chooseHdrLevelsUs(const MeteredRadiance& metered, const RigParams& rig) {
  const double paperUs = exposureForUs(rig, metered.references);
  const double highlightUs = exposureForUs(rig, std::max(metered.window, metered.windowSquare));
  // The window never much brighter than the paper: one exposure holds both.
  if (rig.maxExposureLevels < 2 || highlightUs * kHdrMinRatio >= paperUs)
    return {std::min(paperUs, highlightUs)};
  if (rig.maxExposureLevels < 3 || highlightUs * kHdrMaxStepRatio >= paperUs)
    return {paperUs, highlightUs};
  return {paperUs, std::sqrt(paperUs * highlightUs), highlightUs};
}

SweepTruth simulateSweep(const std::filesystem::path& directory, const io::RecordedSlice& slice,
                         const FrameRenderer& renderer, const SweepSetup& setup,
                         const std::function<void(int, int)>& progress) {
  std::vector<FramePlan> plans =
      planSweep(slice.id, slice.alphaDeg, setup.rig, renderer.camera(), renderer.target());
  std::vector<double> levelsUs;
  if (setup.rig.exposureUs)
    levelsUs = {*setup.rig.exposureUs};
  else if (setup.rig.maxExposureLevels > 1)
    levelsUs = chooseHdrLevelsUs(meterSweep(renderer, setup.rig, plans), setup.rig);
  else
    levelsUs = {chooseExposureUs(renderer, setup.rig, plans)};
  const int levels = static_cast<int>(levelsUs.size());
  if (levels > 1) {
    // Every position of the sweep is taken at every level, by consecutive LED pairs: as many
    // frames per level as a one-exposure sweep has (the same sweep time, frames closer).
    plans = planSweep(slice.id, slice.alphaDeg, setup.rig, renderer.camera(), renderer.target(),
                      levels);
  }
  for (FramePlan& plan : plans) {
    // Levels alternate by LED pair, so each LED-off frame has its LED-on frame's exposure.
    const int pair = setup.rig.alternateLed ? plan.index / 2 : plan.index;
    plan.exposureLevel = pair % levels;
    plan.exposureUs = std::round(levelsUs[plan.exposureLevel] * plan.exposureScale);
  }

  io::Recording header;
  header.createdBy = setup.createdBy + " " + std::string(kVersion);
  header.camera = renderer.camera();
  header.encoding = setup.rig.encoding;
  header.slice = slice;
  header.target = renderer.target();
  io::RecordingWriter writer(directory, header);

  SweepTruth truth;
  truth.material = setup.materialSpec;
  truth.materialDescription = renderer.material().describe();
  truth.slice = slice;
  truth.ledIntensityWPerSr = setup.rig.ledIntensityWPerSr;
  truth.sensorResponse = setup.rig.sensorResponse;
  truth.ambientIrradiance = setup.rig.ambientIrradiance;
  const std::uint64_t sliceSeed =
      setup.rig.seed * 0x9e3779b97f4a7c15ull ^
      (static_cast<std::uint64_t>(slice.id.kind == SliceKind::Axial) << 32) ^
      (std::uint64_t(slice.id.elevations.thetaIDeg) << 16) ^
      std::uint64_t(slice.id.elevations.thetaVDeg);
  for (const FramePlan& plan : plans) {
    const FrameScene scene =
        sceneOf(plan, sliceSeed + static_cast<std::uint64_t>(plan.index) * 7919u);
    io::RecordedFrame entry{"", plan.timestampUs, plan.ledOn, plan.exposureUs, plan.gain};
    if (levels > 1) entry.exposureLevel = plan.exposureLevel;
    const io::RecordedFrame& written = writer.append(renderer.render(scene), entry);
    FrameTruth frameTruth = truthOf(renderer, plan, scene);
    frameTruth.file = written.file;
    truth.frames.push_back(std::move(frameTruth));
    if (progress) progress(plan.index + 1, static_cast<int>(plans.size()));
  }
  writeTruth(directory, truth);
  return truth;
}

std::vector<std::filesystem::path> simulateSession(
    const std::filesystem::path& directory, const FrameRenderer& renderer, const SweepSetup& setup,
    const std::function<void(const std::string&)>& log) {
  std::vector<std::filesystem::path> recordings;
  for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
    for (const ElevationPair& pair : kMeasuredPairs) {
      const io::RecordedSlice slice{{kind, pair}, kAxialOffsetDeg};
      const std::filesystem::path sweep = directory / folderName(slice.id);
      simulateSweep(sweep, slice, renderer, setup);
      if (log) log("wrote " + sweep.string());
      recordings.push_back(sweep);
    }
  }
  return recordings;
}

}  // namespace slicecap::sim
