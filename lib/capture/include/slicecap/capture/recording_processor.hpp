// Offline processing of a recorded sweep: every frame through the pipeline, into azimuth bins.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/capture/window_cell_texture.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::capture {

/// \brief What became of one recording.
struct RecordingResult {
  std::filesystem::path directory;
  SliceId slice;
  std::vector<std::string> frameFiles;  ///< per frame, as in recording.json
  std::vector<FrameOutcome> outcomes;   ///< per frame, in order
  AzimuthBins bins{SliceKind::Axial};
  std::map<RejectReason, int> rejections;  ///< count by reason
  int ambientFrames = 0;
  /// \brief False when the recording has no LED-off frame (the LED on in every frame, as
  /// simulate --no-led-alternation and slicecapd's led_alternate = false record): its samples
  /// keep the room light.
  bool roomLightSubtracted = true;
  /// \brief Exposure levels of an HDR recording (frames[].exposure_level), 1 without: with more,
  /// each level's frames went through their own pipeline (room light of the same level) and the
  /// bins merge the levels (mergeHdrBin).
  int exposureLevels = 1;
  /// \brief How 8-bit frames were decoded: "srgb", or the curve's name ("measured", "linear").
  std::string decoding = "srgb";
  /// \brief The room_light_unseen gate the frames went through (the caller's, else the
  /// recording's own); none: off.
  std::optional<double> roomLightUnseenMm;
  /// \brief The report's entry: per frame the pose, light, gate outcome; per bin its frames;
  /// the bins to pass again, their cells read as `texture` (the sweep's verdict) says.
  nlohmann::json toJson(const CellTexture& texture = {}) const;
  /// \brief The rejections as {"reason name": count}.
  nlohmann::json rejectionsJson() const;
};

/// \brief Runs `directory` (a recording with a slice) through a FramePipeline, decoding 8-bit
/// frames as the recording's `decoding` says unless settings.toneCurve is set. Each LED-on
/// frame's ambient term comes from the LED-off frames before and after it, each sampled at its own
/// pose, interpolated where the camera was (FramePipeline::ambientTermsFor; the first LED-off
/// frame alone for the LED-on frames before it, the last alone after it). A recording without
/// any LED-off frame is processed without a room-light term (settings.requireAmbient is not
/// applied) and says so (roomLightSubtracted). A frame whose PNG is missing,
/// corrupt or of the wrong size is a "bad_frame" rejection naming the file. Throws io::IoError
/// for a bad recording.json (naming the field) and CaptureError for a recording without
/// a slice (e.g. a calibration recording) or with a point one, naming the directory.
/// An HDR recording (frames[].exposure_level) is processed level by level: each level's frames
/// through their own pipeline with PipelineSettings::hdr, so an LED-on frame's room light comes
/// from LED-off frames at its exposure, and the bins merge the levels per cell (mergeHdrBin).
/// `observer` (if set) is called for every frame whose PNG could be read (level by level in an
/// HDR recording, else in order).
RecordingResult processRecording(const std::filesystem::path& directory,
                                 const PipelineSettings& settings = {},
                                 const FrameObserver& observer = {});

/// \brief As above, for `recording` already read from `directory` (a caller that checks every
/// recording.json before processing any). Throws as above.
RecordingResult processRecording(const std::filesystem::path& directory,
                                 const io::Recording& recording,
                                 const PipelineSettings& settings = {},
                                 const FrameObserver& observer = {});

/// \brief The slice `recording` (read from `directory`) holds; CaptureError naming the
/// directory when it holds none (e.g. a calibration recording) or a point "slice".
SliceId sliceOfRecording(const std::filesystem::path& directory, const io::Recording& recording);

}  // namespace slicecap::capture
