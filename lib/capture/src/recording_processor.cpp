// Offline processing of a recording: read each PNG, run the pipeline, bin the samples.
#include "slicecap/capture/recording_processor.hpp"

#include <algorithm>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/pass_again.hpp"
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
  hal::setRecordedEncoding(frame, recording);
  frame.metadata = hal::metadataOf(entry, sequence);
  return frame;
}

// A located LED-off frame of the longest exposure level: where it is in the recording, when it was
// taken, and its pose.
struct LocatedOff {
  std::size_t index = 0;
  std::int64_t timestampUs = 0;
  vision::Pose pose;
};

// The LED-off frames of `group` that were located, in time order (the group's outcomes are in).
std::vector<LocatedOff> locatedOffFrames(const io::Recording& recording,
                                         const std::vector<std::size_t>& group,
                                         const RecordingResult& result) {
  std::vector<LocatedOff> located;
  for (std::size_t i : group) {
    const FrameOutcome& outcome = result.outcomes[i];
    if (outcome.kind == FrameOutcome::Kind::Ambient && outcome.measurement.pose)
      located.push_back({i, recording.frames[i].timestampUs, *outcome.measurement.pose});
  }
  return located;
}

// Gives a shorter level's pipeline, before each of its LED-on frames, the longest level's located
// LED-off frames on both sides of it (FramePipeline::setStandInAmbientFrames): a short level's own
// LED-off frames are too dark to be located. Each PNG is read once while it stays a neighbour; one
// that cannot be read is left out (that frame's own turn reports it).
class StandInFeeder {
 public:
  using ReadFrame = std::function<hal::Frame(std::size_t)>;
  StandInFeeder(const std::vector<LocatedOff>& source, ReadFrame read)
      : source_(source), read_(std::move(read)) {}

  void feed(FramePipeline& pipeline, std::int64_t timeUs) {
    if (source_.empty()) return;
    const auto after = std::find_if(source_.begin(), source_.end(),
                                     [&](const LocatedOff& f) { return f.timestampUs > timeUs; });
    std::vector<const LocatedOff*> wanted;
    if (after != source_.begin()) wanted.push_back(&*std::prev(after));
    if (after != source_.end()) wanted.push_back(&*after);
    // The neighbours kept move over from frames_ (no copy); only a new one is read.
    std::map<std::size_t, hal::Frame> kept;
    std::vector<LocatedAmbientFrame> frames;
    for (const LocatedOff* f : wanted) {
      if (auto node = frames_.extract(f->index)) {
        kept.insert(std::move(node));
      } else {
        try {
          kept.emplace(f->index, read_(f->index));
        } catch (const io::IoError&) {
          continue;
        }
      }
      frames.push_back({kept.at(f->index), f->pose});
    }
    frames_ = std::move(kept);
    pipeline.setStandInAmbientFrames(std::move(frames));
  }

 private:
  const std::vector<LocatedOff>& source_;
  ReadFrame read_;
  std::map<std::size_t, hal::Frame> frames_;  // the current neighbours, by recording index
};

// The longest level's pipeline's latest location (FramePipeline::latestLocation) after its frame
// taken at `frameTimeUs`.
struct LocationAfter {
  std::int64_t frameTimeUs = 0;
  std::optional<TimedPose> location;
};

// What a shorter level's group takes from the longest level's (both empty for the longest level
// or one exposure).
struct FromLongestLevel {
  // Its located LED-off frames, standing in for the shorter level's room light.
  std::vector<LocatedOff> standIns;
  // Its latest location after each of its frames, in time order: before each frame of a shorter
  // level the pipeline tracks from the location after the longest level's last frame before it,
  // which is what the live loop's pipelines, fed the frames in time order, hand on
  // (frame_processor.cpp).
  std::vector<LocationAfter> locations;

  // The location after its last frame taken before `timeUs`; none before its first frame or
  // while it had lost the target.
  std::optional<TimedPose> locationBefore(std::int64_t timeUs) const {
    const auto after = std::partition_point(
        locations.begin(), locations.end(),
        [&](const LocationAfter& l) { return l.frameTimeUs < timeUs; });
    if (after == locations.begin()) return std::nullopt;
    return std::prev(after)->location;
  }
};

// The frames `group` (indices into recording.frames, in time order) through one pipeline; their
// outcomes go to result.outcomes at their indices. `longest`: what a shorter level's group takes
// from the longest level's; `locations` (if set) gets this group's latest location after each
// frame.
void processGroup(const std::filesystem::path& directory, const io::Recording& recording,
                  const std::vector<std::size_t>& group, const PipelineSettings& offline,
                  const FrameObserver& observer, const FromLongestLevel& longest,
                  RecordingResult& result, std::vector<LocationAfter>* locations) {
  FramePipeline pipeline(recording.target, recording.camera, offline);
  const auto readFrame = [&](std::size_t i) {
    return frameOf(io::readPng(io::framePath(directory, recording.frames[i])), recording,
                   recording.frames[i], i);
  };
  StandInFeeder feeder(longest.standIns, readFrame);
  if (!offline.offlineTwoSidedAmbient) {
    // As live, except that LED-on frames before the first LED-off one use that one.
    for (std::size_t i : group) {
      if (recording.frames[i].ledOn) continue;
      try {
        pipeline.setAmbientFrame(readFrame(i));
      } catch (const io::IoError&) {
        continue;  // counted as bad_frame when its turn comes
      }
      break;
    }
  }
  // `following` holds a position in `group`, read ahead and used in its turn.
  std::optional<std::pair<std::size_t, hal::Frame>> following;
  for (std::size_t n = 0; n < group.size(); ++n) {
    const std::size_t i = group[n];
    const io::RecordedFrame& entry = recording.frames[i];
    result.frameFiles[i] = entry.file;
    FrameOutcome outcome;
    // Before the LED-off frame after it is read ahead and located (two-sided), as its own turn
    // would be.
    if (const std::optional<TimedPose> location = longest.locationBefore(entry.timestampUs))
      pipeline.trackFrom(*location);
    try {
      if (offline.offlineTwoSidedAmbient && entry.ledOn && (!following || following->first < n)) {
        following.reset();
        for (std::size_t m = n + 1; m < group.size() && !following; ++m) {
          if (recording.frames[group[m]].ledOn) continue;
          try {
            following.emplace(m, readFrame(group[m]));
            pipeline.setFollowingAmbientFrame(following->second);
          } catch (const io::IoError&) {
            break;  // counted as bad_frame when its turn comes; one-sided until then
          }
        }
      }
      const hal::Frame frame =
          following && following->first == n ? following->second : readFrame(i);
      if (entry.ledOn) feeder.feed(pipeline, entry.timestampUs);
      outcome = pipeline.process(frame, result.slice);
      // An LED-on frame leaves the pipeline's LED-off frames as they were: its own term.
      if (observer)
        observer(frame, outcome,
                 entry.ledOn ? pipeline.ambientTermsFor(frame.metadata.timestampUs,
                                                        outcome.measurement.pose)
                             : std::vector<AmbientTerm>{});
    } catch (const io::IoError& error) {
      outcome.kind = FrameOutcome::Kind::Rejected;
      outcome.rejectReason = RejectReason::BadFrame;
      outcome.detail = error.what();
    }
    result.outcomes[i] = std::move(outcome);
    if (locations) locations->push_back({entry.timestampUs, pipeline.latestLocation()});
  }
}

// The settings a recording is processed with. Offline the LED-off frames on both sides of each
// LED-on frame are known: each is located and interpolated (FramePipeline::setFollowingAmbientFrame).
// No camera waits on a recording either: every frame is searched as long as it takes (the live
// loop spreads a lost target's search over frames, rejecting them as "detection_deferred").
// `--ambient previous` reproduces the live loop, budget included. Notes in `result` what the
// recording decided (room light, decoding).
PipelineSettings offlineSettings(const io::Recording& recording, const PipelineSettings& settings,
                                 RecordingResult& result) {
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
  // The room-light gate the capture had, unless the caller set one (0: off).
  if (!offline.maxRoomLightDistanceMm) offline.maxRoomLightDistanceMm = recording.roomLightUnseenMm;
  if (offline.maxRoomLightDistanceMm.value_or(0.0) > 0.0)
    result.roomLightUnseenMm = offline.maxRoomLightDistanceMm;
  return offline;
}

// The recording's frame indices by exposure level (level 0, the longest, first; one group for a
// recording without levels), each in time order.
std::vector<std::vector<std::size_t>> levelGroups(const io::Recording& recording) {
  std::vector<std::vector<std::size_t>> groups(1);
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    const std::size_t level = static_cast<std::size_t>(recording.frames[i].exposureLevel.value_or(0));
    if (groups.size() <= level) groups.resize(level + 1);
    groups[level].push_back(i);
  }
  return groups;
}

// The outcomes, in recording order, into the bins and the counts.
void binOutcomes(const io::Recording& recording, RecordingResult& result) {
  for (std::size_t i = 0; i < recording.frames.size(); ++i) {
    FrameOutcome& outcome = result.outcomes[i];
    if (outcome.kind == FrameOutcome::Kind::Sample) {
      outcome.sample->frameIndex = i;
      if (outcome.sample->hdr)
        outcome.sample->hdr->exposureLevel = recording.frames[i].exposureLevel.value_or(0);
      result.bins.add(*outcome.sample);
    } else if (outcome.kind == FrameOutcome::Kind::Ambient) {
      ++result.ambientFrames;
    } else {
      ++result.rejections[outcome.rejectReason];
    }
  }
}

}  // namespace

SliceId sliceOfRecording(const std::filesystem::path& directory, const io::Recording& recording) {
  if (!recording.slice)
    throw CaptureError(directory.string() +
                       ": recording.json has no slice (a calibration recording?)");
  // A sweep is of an axial or a diagonal slice; a point sample falls in no azimuth bin.
  if (recording.slice->id.kind == SliceKind::Point)
    throw CaptureError(directory.string() +
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
  PipelineSettings offline = offlineSettings(recording, settings, result);
  // An HDR recording (frames[].exposure_level) is processed level by level, each with its own
  // pipeline: an LED-on frame's room light then comes from the LED-off frames of its own
  // exposure, and the bins merge the levels (hdr_merge.hpp). One level: the frames in order.
  const std::vector<std::vector<std::size_t>> groups = levelGroups(recording);
  result.exposureLevels = static_cast<int>(groups.size());
  offline.hdr = result.exposureLevels > 1;
  result.frameFiles.resize(recording.frames.size());
  result.outcomes.resize(recording.frames.size());
  // The longest level first: with LED-off frames located (offline, two-sided), they stand in for
  // the room light of the shorter levels' LED-on frames whose own LED-off frames were not.
  // Its locations guide the shorter levels' marker search (FramePipeline::trackFrom).
  FromLongestLevel longest;
  processGroup(directory, recording, groups[0], offline, observer, {}, result,
               groups.size() > 1 ? &longest.locations : nullptr);
  if (offline.poseAmbientFrames && groups.size() > 1)
    longest.standIns = locatedOffFrames(recording, groups[0], result);
  for (std::size_t level = 1; level < groups.size(); ++level)
    processGroup(directory, recording, groups[level], offline, observer, longest, result, nullptr);
  binOutcomes(recording, result);
  return result;
}

nlohmann::json RecordingResult::rejectionsJson() const {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [reason, count] : rejections)
    out[std::string(toString(reason))] = count;
  return out;
}

nlohmann::json RecordingResult::toJson(const CellTexture& texture) const {
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
    if (o.sample && o.sample->hdr) f["exposure_level"] = o.sample->hdr->exposureLevel;
    if (o.kind == FrameOutcome::Kind::Rejected) f["reason"] = toString(o.rejectReason);
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
  // The bins to pass again had the recording been a live sweep (docs/method.md §9.5).
  nlohmann::json passAgain = nlohmann::json::array();
  const std::vector<PassAgainBin> toPassAgain =
      slice.kind == SliceKind::Point ? std::vector<PassAgainBin>{}
                                     : binsToPassAgain(bins, slice, SweepProgress::Finished, {}, texture);
  for (const PassAgainBin& bin : toPassAgain)
    passAgain.push_back({{"bin", bin.bin}, {"azimuth_deg", bin.azimuthDeg},
                         {"reason", toString(bin.reason)}});
  return {{"recording", directory.string()},
          {"slice", toString(slice)},
          {"decoding", decoding},
          {"bins_filled", bins.filledCount()},
          {"exposure_levels", exposureLevels},
          {"room_light_unseen_mm", roomLightUnseenMm ? nlohmann::json(*roomLightUnseenMm)
                                                     : nlohmann::json(nullptr)},
          {"room_light", roomLightSubtracted
                             ? "subtracted (the LED-off frames)"
                             : "not subtracted: the recording has no LED-off frame"},
          {"rejections", rejectionsJson()},
          {"frames", frames},
          {"bins", binList},
          {"pass_again", passAgain}};
}

}  // namespace slicecap::capture
