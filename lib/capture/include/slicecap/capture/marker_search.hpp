// Where and how finely each frame is searched for the target's markers, within a per-frame budget:
// tracked from the latest pose, widened after a miss, and a lost target re-acquired over frames.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::capture {

/// \brief One detector call: the part of the image and the scale it is searched at.
struct SearchPass {
  PixelRect area;
  DetectionScale scale;
};

/// \brief What one frame's search did and found.
struct MarkerSearchResult {
  /// \brief The markers of the pass (or passes' best) that was used; may be empty.
  std::vector<DetectedMarker> markers;
  /// \brief The scale of the tracked search whose markers were used; none when they came from
  /// the re-acquisition passes (no pose to track from).
  std::optional<DetectionScale> trackedScale;
  int passes = 0;         ///< detector calls made on this frame
  double workPx = 0.0;    ///< their summed detectionWorkPx, at most the frame budget
  /// \brief Fewer than the wanted markers were found and a pass the search wanted was left to the
  /// next frames because this frame's budget was spent: the "detection_deferred" rejection.
  bool deferred = false;
};

/// \brief Searches frames for the target's markers so that no frame costs more than
/// MarkerDetectorSettings::frameBudgetPx of detector work (bench/capture_bench.cpp measures what
/// that is in milliseconds; docs/detection.md). With a recent pose: the sheet's predicted region
/// at the coarsest scale its tag cells allow; then, as the budget allows, the same region finer
/// (too few markers for a good pose) or a wider region (the target moved further than predicted).
/// Without one (the first frames, or a target lost for more than a few frames): the whole frame
/// at a cheap scale, then at finer ones, each frame taking the next passes of that fixed list
/// (each pass fits the budget; a whole frame at full resolution is split into tiles), so a lost
/// target is found again within a bounded number of frames. Not thread-safe; one per frame loop.
class MarkerSearch {
 public:
  /// \brief Throws CaptureError as MarkerDetector does, or naming a budget that is not
  /// positive.
  MarkerSearch(const vision::TargetGeometry& target, const vision::CameraModel& camera,
               MarkerDetectorSettings settings, int minMarkers);

  /// \brief One frame's search. `countsAsMiss`: the frame is an LED-on frame; unless located()
  /// follows, it is one more frame without a pose, and after
  /// MarkerDetectorSettings::trackingPatienceFrames of those the last pose is dropped (checked as
  /// the next such frame starts). LED-off frames search only while no pose is tracked (to
  /// re-acquire the target) and pass false.
  MarkerSearchResult search(const hal::Frame& frame, bool countsAsMiss = true);
  /// \brief The frame just searched gave `pose`, good enough to track from: the next frames are
  /// searched around it, and the re-acquisition passes start over when next needed.
  void located(const vision::Pose& pose);
  /// \brief A pose another search located (a longer HDR exposure level's, more recent than this
  /// search's own) guides the next frames as located() does, but the re-acquisition passes go on
  /// from where they were: were it handed on before every frame, they would otherwise never get
  /// past the first.
  void trackFrom(const vision::Pose& pose);
  /// \brief True while a recent pose guides the search.
  bool tracking() const { return lastPose_.has_value(); }
  /// \brief The pose the search tracks from, if any.
  const std::optional<vision::Pose>& lastPose() const { return lastPose_; }
  /// \brief The fixed list of passes that re-acquire a lost target, in the order they are run.
  const std::vector<SearchPass>& acquisitionPasses() const { return acquisition_; }

 private:
  vision::TargetGeometry target_;
  vision::CameraModel camera_;
  MarkerDetectorSettings settings_;
  int minMarkers_;
  MarkerDetector detector_;
  std::vector<SearchPass> acquisition_;
  std::size_t nextAcquisition_ = 0;
  std::optional<vision::Pose> lastPose_;
  int framesSinceLastPose_ = 0;
};

}  // namespace slicecap::capture
