// Offline processing of a recording: read each PNG, run the pipeline, bin the samples.
#include "slicecap/capture/recording_processor.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <limits>
#include <stdexcept>

#include "slicecap/hal/recorded_frame.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::capture {
namespace {

nlohmann::json directionJson(const std::optional<Direction>& d) {
  if (!d) return nullptr;
  return {{"theta_deg", d->thetaDeg}, {"phi_deg", d->phiDeg}};
}

std::string kindName(FrameOutcome::Kind kind) {
  switch (kind) {
    case FrameOutcome::Kind::Sample:
      return "sample";
    case FrameOutcome::Kind::Ambient:
      return "ambient";
    case FrameOutcome::Kind::Rejected:
      return "rejected";
  }
  return "rejected";
}

hal::Frame frameOf(Image image, const io::Recording& recording, const io::RecordedFrame& entry,
                   std::uint64_t sequence) {
  hal::Frame frame;
  frame.image = std::move(image);
  frame.encoding = recording.encoding;
  frame.metadata = hal::metadataOf(entry, sequence);
  return frame;
}

}  // namespace

SliceId sliceOfRecording(const std::filesystem::path& directory, const io::Recording& recording) {
  if (!recording.slice)
    throw std::invalid_argument(directory.string() +
                                ": recording.json has no slice (a calibration recording?)");
  // A sweep is of an axial or a diagonal slice; a point sample falls in no azimuth bin.
  if (recording.slice->id.kind == SliceKind::Point)
    throw std::invalid_argument(directory.string() +
                                ": recording.json: slice kind \"point\" is no sweep (expected "
                                "\"axial\" or \"diagonal\")");
  return recording.slice->id;
}

RecordingResult processRecording(const std::filesystem::path& directory,
                                 const PipelineSettings& settings, const FrameObserver& observer) {
  return processRecording(directory, io::readRecording(directory), settings, observer);
}

RecordingResult processRecording(const std::filesystem::path& directory,
                                 const io::Recording& recording, const PipelineSettings& settings,
                                 const FrameObserver& observer) {
  RecordingResult result;
  result.directory = directory;
  result.slice = sliceOfRecording(directory, recording);
  result.bins = AzimuthBins(result.slice.kind);
  // Offline the LED-off frames on both sides of each LED-on frame are known: each is located
  // and interpolated (FramePipeline::setFollowingAmbientFrame).
  // No camera waits on a recording either: every frame is searched as long as it takes (the live
  // loop spreads a lost target's search over frames, rejecting them as "detection_deferred").
  // `--ambient previous` reproduces the live loop, budget included.
  PipelineSettings offline = settings;
  offline.poseAmbientFrames = settings.offlineTwoSidedAmbient;
  // The recording decides: with the LED on in every frame there is no room light to subtract
  // (as slicecapd with led_alternate = false), not a missing LED-off frame for every sample.
  if (std::none_of(recording.frames.begin(), recording.frames.end(),
                   [](const io::RecordedFrame& f) { return !f.ledOn; })) {
    offline.requireAmbient = false;
    result.roomLightSubtracted = false;
  }
  // The frames are read as they were taken: through the curve measured at sweep start when the
  // recording says so (a caller's own curve, e.g. sRGB to compare, wins).
  if (!offline.toneCurve)
    offline.toneCurve =
        recording.decoding.value_or(io::RecordedDecoding::defaultFor(recording.encoding))
            .toneCurve();
  if (offline.toneCurve) result.decoding = offline.toneCurve->name();
  if (settings.offlineTwoSidedAmbient)
    offline.detector.frameBudgetPx = std::numeric_limits<double>::infinity();
  FramePipeline pipeline(recording.target, recording.camera, offline);
  const auto readFrame = [&](std::size_t i) {
    return frameOf(io::readPng(io::framePath(directory, recording.frames[i])), recording,
                   recording.frames[i], i);
  };
  if (!settings.offlineTwoSidedAmbient) {
    // As live, except that LED-on frames before the first LED-off one use that one.
    for (std::size_t i = 0; i < recording.frames.size(); ++i) {
      if (recording.frames[i].ledOn) continue;
      try {
        pipeline.setAmbientFrame(readFrame(i));
      } catch (const io::IoError&) {
        continue;  // counted as bad_frame when its turn comes
      }
      break;
    }
  }
  std::optional<std::pair<std::size_t, hal::Frame>> following;  // read ahead, used in its turn
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const io::RecordedFrame& entry = recording.frames[i];
    result.frameFiles.push_back(entry.file);
    FrameOutcome outcome;
    try {
      if (settings.offlineTwoSidedAmbient && entry.ledOn && (!following || following->first < i)) {
        following.reset();
        for (std::size_t j = i + 1; j < recording.frames.size() && !following; ++j) {
          if (recording.frames[j].ledOn) continue;
          try {
            following.emplace(j, readFrame(j));
            pipeline.setFollowingAmbientFrame(following->second);
          } catch (const io::IoError&) {
            break;  // counted as bad_frame when its turn comes; one-sided until then
          }
        }
      }
      const hal::Frame frame =
          following && following->first == i ? following->second : readFrame(i);
      outcome = pipeline.process(frame, result.slice);
      // An LED-on frame leaves the pipeline's LED-off frames as they were: its own term.
      if (observer)
        observer(frame, outcome,
                 entry.ledOn ? pipeline.ambientTermsFor(frame.metadata.timestampUs)
                             : std::vector<AmbientTerm>{});
    } catch (const io::IoError& error) {
      outcome.kind = FrameOutcome::Kind::Rejected;
      outcome.rejectReason = "bad_frame";
      outcome.detail = error.what();
    }
    if (outcome.kind == FrameOutcome::Kind::Sample) {
      outcome.sample->frameIndex = i;
      result.bins.add(*outcome.sample);
    } else if (outcome.kind == FrameOutcome::Kind::Ambient) {
      ++result.ambientFrames;
    } else {
      ++result.rejections[outcome.rejectReason];
    }
    result.outcomes.push_back(std::move(outcome));
  }
  return result;
}

nlohmann::json RecordingResult::toJson() const {
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    const FrameOutcome& o = outcomes[i];
    const auto& m = o.measurement;
    nlohmann::json f = {{"file", frameFiles[i]},
                        {"outcome", kindName(o.kind)},
                        {"markers", m.markerCount},
                        {"view", directionJson(m.view)},
                        {"camera_distance_mm", m.cameraDistanceMm},
                        {"pose_residual_px", m.poseResidualPx},
                        {"sharpness", m.sharpness},
                        {"nominal_light", directionJson(m.nominalLight)},
                        {"measured_light", directionJson(m.measuredLight)},
                        {"measured_light_sigma_deg", m.measuredLightSigmaDeg}};
    // How the markers were found: the tracked search's scale, or the whole frame.
    if (const auto& scale = m.trackedScale)
      f["detection"] = {{"tracked", true},
                        {"decimation", scale->quadDecimate},
                        {"bin", {scale->binX, scale->binY}}};
    else if (m.markerCount > 0)
      f["detection"] = {{"tracked", false}};
    if (m.referenceDisagreement)
      f["white_references"] = {{"disagreement", *m.referenceDisagreement},
                               {"allowed", m.referenceDisagreementLimit.value_or(0.0)}};
    if (o.kind == FrameOutcome::Kind::Rejected) f["reason"] = o.rejectReason;
    if (!o.detail.empty()) f["detail"] = o.detail;
    if (o.sample) {
      f["light"] = directionJson(o.sample->light);
      f["brdf"] = {o.sample->value[0], o.sample->value[1], o.sample->value[2]};
      f["bin"] = bins.binOf(*o.sample);
    }
    frames.push_back(std::move(f));
  }
  nlohmann::json binList = nlohmann::json::array();
  for (int b = 0; b < bins.binCount(); ++b) {
    nlohmann::json used = nlohmann::json::array();
    for (const FrameSample& s : bins.samplesIn(b))
      used.push_back(s.frameIndex);
    binList.push_back({{"bin", b}, {"frames", used}});
  }
  return {{"recording", directory.string()},
          {"slice", toString(slice)},
          {"decoding", decoding},
          {"bins_filled", bins.filledCount()},
          {"room_light", roomLightSubtracted
                             ? "subtracted (the LED-off frames)"
                             : "not subtracted: the recording has no LED-off frame"},
          {"rejections", rejections},
          {"frames", frames},
          {"bins", binList}};
}

}  // namespace slicecap::capture
