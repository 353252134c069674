// The frame pipeline's readings of an LED-on frame at its pose: the window, the white references
// and the point light fitted to them, the HDR cells (FramePipeline::State).
#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "frame_pipeline_state.hpp"

namespace slicecap::capture {

std::optional<frame_checks::GateFailure> FramePipeline::State::readWindow(
    const hal::Frame& frame, const vision::Pose& pose, AreaReading* window) const {
  AreaSpec spec = windowArea;
  spec.clipFraction = settings.clipFraction;
  *window = readArea(frame, pose, camera, spec, settings.noise, *codes);
  if (!window->inside)
    return frame_checks::GateFailure{RejectReason::WindowOccluded, "window out of the image"};
  if (window->clipped && !settings.hdr)
    return frame_checks::GateFailure{RejectReason::WindowClipped, "window saturated"};
  return std::nullopt;
}

std::optional<frame_checks::GateFailure> FramePipeline::State::readReferences(
    const hal::Frame& frame, const vision::Pose& pose, const std::vector<AmbientTerm>& roomLight,
    const AreaReading& window, Rgb* windowRadiance, std::vector<ReferenceObservation>* observations,
    std::vector<ReferenceObservation>* unlit, RoomShare* share) const {
  *windowRadiance = window.mean - ambientAt(roomLight, windowArea, pose).mean;
  for (const auto& reference : references) {
    AreaSpec spec = reference.area;
    spec.clipFraction = settings.clipFraction;
    const AreaReading area = readArea(frame, pose, camera, spec, settings.noise, *codes);
    if (!area.inside) continue;
    if (area.clipped)
      return frame_checks::GateFailure{RejectReason::WindowClipped, "white reference saturated"};
    const AreaReading room = ambientAt(roomLight, reference.area, pose);
    const Rgb value = area.mean - room.mean;
    for (int c = 0; c < 3; ++c) {
      share->room += room.mean[c];
      share->led += value[c];
    }
    Rgb sigma;
    for (int c = 0; c < 3; ++c)
      sigma[c] = std::sqrt(area.variance[c] + room.variance[c]);
    const ReferenceObservation observation{
        {reference.centre.x(), reference.centre.y(), 0.0}, value, reference.albedo, sigma};
    // No LED light (the arm covers it, or noise in a dark frame): not for the fit, but checked
    // against the fitted light (fitLight).
    (value.minChannel() > 0 ? observations : unlit)->push_back(observation);
  }
  if (observations->size() < 5)
    return frame_checks::GateFailure{RejectReason::WindowOccluded,
                                     "white references out of the image"};
  return std::nullopt;
}

std::optional<frame_checks::GateFailure> FramePipeline::State::fitLight(
    const std::vector<ReferenceObservation>& observations,
    const std::vector<ReferenceObservation>& unlit, const Direction& nominalLight, LightFit* fit,
    double* limit) const {
  LightFitParams fitParams;
  const UnitVector toLight = toUnitVector(nominalLight);
  fitParams.initialPositionMm = {toLight.x * settings.nominalLightDistanceMm,
                                 toLight.y * settings.nominalLightDistanceMm,
                                 toLight.z * settings.nominalLightDistanceMm};
  if (const std::optional<std::string> problem = lightFitProblem(observations, fitParams))
    return frame_checks::GateFailure{RejectReason::WindowOccluded, *problem};
  *fit = fitPointLight(observations, fitParams);
  if (!fit->converged)
    return frame_checks::GateFailure{RejectReason::WindowOccluded, "light fit: " + fit->message};
  *limit = settings.maxReferenceResidual +
           frame_checks::noiseAllowance(*fit, settings.referenceNoiseSigmas);
  if (fit->weightedResidualRms > *limit)
    return frame_checks::GateFailure{RejectReason::WindowOccluded,
                                     "white references disagree by " +
                                         std::to_string(fit->weightedResidualRms) +
                                         ", noise and margin allow " + std::to_string(*limit)};
  for (const ReferenceObservation& o : unlit) {
    const Rgb irradiance = fit->light.irradianceAt(o.point);
    for (int c = 0; c < 3; ++c) {
      const double expected = o.albedo[c] / std::numbers::pi * irradiance[c];
      if (expected - o.radiance[c] >
          settings.referenceNoiseSigmas * o.sigma[c] + settings.maxReferenceResidual * expected)
        return frame_checks::GateFailure{
            RejectReason::WindowOccluded,
            "a white reference (at " + std::to_string(o.point.x) + ", " +
                std::to_string(o.point.y) + " mm) gets no LED light, " +
                std::to_string(expected / o.sigma[c]) + " sigma expected"};
    }
  }
  return std::nullopt;
}

std::vector<HdrCell> FramePipeline::State::readCells(
    const hal::Frame& frame, const vision::Pose& pose,
    const std::vector<AmbientTerm>& roomLight) const {
  const vision::RectMm& r = windowArea.rectMm;
  const int n = kHdrCellsPerSide;
  const double scale =
      frame_checks::exposureKnown(frame) ? frame.metadata.exposureUs * frame.metadata.gain : 1.0;
  std::vector<HdrCell> cells;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x0 = r.xMinMm + i * r.widthMm() / n, y0 = r.yMinMm + j * r.heightMm() / n;
      const AreaSpec spec{
          {x0, y0, x0 + r.widthMm() / n, y0 + r.heightMm() / n}, 0.0, settings.clipFraction};
      const AreaReading area = readArea(frame, pose, camera, spec, settings.noise, *codes);
      const AreaReading room = ambientAt(roomLight, spec, pose);
      HdrCell cell;
      cell.radiance = area.mean - room.mean;
      for (int c = 0; c < 3; ++c)
        cell.variance[c] = area.variance[c] + room.variance[c];
      // A cell darker than its noise can read below 0 (the censored mean of an area mostly at
      // code 0, or RAW below its black level); as exposed it was at 0 of full scale.
      cell.level = std::max(0.0, area.mean.maxChannel()) * scale;
      cell.clipped = area.clipped || !area.inside;
      cells.push_back(cell);
    }
  return cells;
}

}  // namespace slicecap::capture
