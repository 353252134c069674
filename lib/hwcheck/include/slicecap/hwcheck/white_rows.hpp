// The target's white references in a frame, row by row: where the LED's switch shows.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/linear_view.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::hwcheck {

/// \brief The target's pose in a frame from its markers (the frame pipeline's detector and planar
/// pose), or nullopt when fewer than `minMarkers` are found or the pose does not fit.
std::optional<vision::Pose> locateTarget(const hal::Frame& frame,
                                         const vision::TargetGeometry& target,
                                         const vision::CameraModel& camera, int minMarkers = 4);

/// \brief The pixels of the white reference patches (inset by a fifth of their smaller side, so
/// a slightly wrong pose mixes in nothing else), grouped by image row.
struct WhiteRows {
  int widthPx = 0, heightPx = 0;
  std::vector<std::vector<int>> columnsByRow;  ///< per image row, the white pixels' columns
  int firstRow = -1, lastRow = -1;             ///< rows holding any (-1: none)

  /// \brief Per row, the mean of R+G+B decoded through `codes` over its white pixels (0 where
  /// the row has none). Throws HardwareCheckError when the frame's size differs.
  std::vector<double> rowMeans(const hal::Frame& frame, const capture::CodeTable& codes) const;
  /// \brief The mean over every white pixel (R+G+B decoded), same throws.
  double mean(const hal::Frame& frame, const capture::CodeTable& codes) const;
  /// \brief Whether `row` holds at least `minPixels` white pixels.
  bool usable(int row, int minPixels = 8) const;
};

/// \brief The white rows of `target` seen through `pose`.
WhiteRows whiteRowsOf(const vision::TargetGeometry& target, const vision::CameraModel& camera,
                      const vision::Pose& pose);

}  // namespace slicecap::hwcheck
