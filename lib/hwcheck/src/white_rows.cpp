// The white references' pixels by row, from the target's pose.
#include "slicecap/hwcheck/white_rows.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "slicecap/capture/marker_detector.hpp"
#include "slicecap/capture/planar_pose.hpp"
#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {

std::optional<vision::Pose> locateTarget(const hal::Frame& frame,
                                         const vision::TargetGeometry& target,
                                         const vision::CameraModel& camera, int minMarkers) {
  capture::MarkerDetector detector;
  std::vector<capture::PlaneCorrespondence> corners;
  int markers = 0;
  for (const capture::DetectedMarker& marker : detector.detect(frame))
    if (const vision::Marker* geometry = target.findMarker(marker.id)) {
      ++markers;
      for (int c = 0; c < 4; ++c)
        corners.push_back(
            {{geometry->cornersMm[c].xMm, geometry->cornersMm[c].yMm}, marker.cornersPx[c]});
    }
  if (markers < minMarkers) return std::nullopt;
  const auto estimate = capture::estimatePlanarPose(corners, camera);
  // 1.5 px: the response fit's limit for a pose good enough to read patches by.
  if (!estimate || estimate->residualRmsPx > 1.5) return std::nullopt;
  return estimate->pose;
}

WhiteRows whiteRowsOf(const vision::TargetGeometry& target, const vision::CameraModel& camera,
                      const vision::Pose& pose) {
  WhiteRows rows;
  rows.widthPx = camera.intrinsics.widthPx;
  rows.heightPx = camera.intrinsics.heightPx;
  rows.columnsByRow.resize(std::size_t(std::max(rows.heightPx, 0)));
  std::vector<std::set<int>> sets(rows.columnsByRow.size());
  // Pixel centres sit at integer coordinates (vision::CameraIntrinsics). Sample each patch on a 0.1 mm grid (finer than a pixel at any working distance) and keep the
  // pixels hit: simpler than rasterising a distorted quadrilateral, and exact enough.
  for (const vision::Patch& patch : target.patches) {
    if (patch.kind != vision::PatchKind::White) continue;
    const vision::RectMm& r = patch.rect;
    const double inset = 0.2 * std::min(r.widthMm(), r.heightMm());
    for (double y = r.yMinMm + inset; y < r.yMaxMm - inset; y += 0.1)
      for (double x = r.xMinMm + inset; x < r.xMaxMm - inset; x += 0.1) {
        const auto px = camera.project(pose.toCamera({x, y, 0.0}));
        if (!px) continue;
        const int col = int(std::lround((*px)[0])), row = int(std::lround((*px)[1]));
        if (col < 0 || row < 0 || col >= rows.widthPx || row >= rows.heightPx) continue;
        sets[std::size_t(row)].insert(col);
      }
  }
  for (std::size_t row = 0; row < sets.size(); ++row) {
    rows.columnsByRow[row].assign(sets[row].begin(), sets[row].end());
    if (!sets[row].empty()) {
      if (rows.firstRow < 0) rows.firstRow = int(row);
      rows.lastRow = int(row);
    }
  }
  return rows;
}

namespace {
void checkSize(const WhiteRows& rows, const hal::Frame& frame) {
  if (frame.image.width != rows.widthPx || frame.image.height != rows.heightPx ||
      frame.image.channels != 3)
    throw HardwareCheckError("white rows: the frame is " + std::to_string(frame.image.width) +
                             " x " + std::to_string(frame.image.height) + " x " +
                             std::to_string(frame.image.channels) + ", the rows are for " +
                             std::to_string(rows.widthPx) + " x " +
                             std::to_string(rows.heightPx) + " RGB");
}
double pixelSum(const hal::Frame& frame, const capture::CodeTable& codes, int row, int col) {
  const std::size_t at = (std::size_t(row) * frame.image.width + col) * 3;
  const auto& s = frame.image.samples;
  if (frame.encoding == PixelEncoding::Srgb8) return codes[s[at]] + codes[s[at + 1]] + codes[s[at + 2]];
  return hal::linear16Value(s[at], frame.black16) + hal::linear16Value(s[at + 1], frame.black16) +
         hal::linear16Value(s[at + 2], frame.black16);
}
}  // namespace

std::vector<double> WhiteRows::rowMeans(const hal::Frame& frame,
                                        const capture::CodeTable& codes) const {
  checkSize(*this, frame);
  std::vector<double> means(columnsByRow.size(), 0.0);
  for (std::size_t row = 0; row < columnsByRow.size(); ++row) {
    const std::vector<int>& cols = columnsByRow[row];
    if (cols.empty()) continue;
    double sum = 0.0;
    for (int col : cols) sum += pixelSum(frame, codes, int(row), col);
    means[row] = sum / double(cols.size());
  }
  return means;
}

double WhiteRows::mean(const hal::Frame& frame, const capture::CodeTable& codes) const {
  checkSize(*this, frame);
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t row = 0; row < columnsByRow.size(); ++row)
    for (int col : columnsByRow[row]) {
      sum += pixelSum(frame, codes, int(row), col);
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

bool WhiteRows::usable(int row, int minPixels) const {
  return row >= 0 && row < int(columnsByRow.size()) &&
         int(columnsByRow[std::size_t(row)].size()) >= minPixels;
}

}  // namespace slicecap::hwcheck
