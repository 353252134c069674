// MarkerSearch: tracked passes around the latest pose, then re-acquisition passes, in budget.
#include "slicecap/capture/marker_search.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/vision/tag_family.hpp"

namespace slicecap::capture {
namespace {

int countKnown(const std::vector<DetectedMarker>& markers, const vision::TargetGeometry& target) {
  return static_cast<int>(std::count_if(markers.begin(), markers.end(), [&](const auto& m) {
    return target.findMarker(m.id) != nullptr;
  }));
}

// The image box of the sheet seen from `pose`, grown by `growth` of its size plus 16 px on every
// side.
std::optional<PixelRect> sheetRegion(const vision::Pose& pose, const vision::CameraModel& camera,
                                     const vision::RectMm& sheet, double growth) {
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (const double x : {sheet.xMinMm, sheet.xMaxMm})
    for (const double y : {sheet.yMinMm, sheet.yMaxMm}) {
      const auto px = camera.project(pose.toCamera({x, y, 0.0}));
      if (!px) return std::nullopt;
      x0 = std::min(x0, px->x()), x1 = std::max(x1, px->x());
      y0 = std::min(y0, px->y()), y1 = std::max(y1, px->y());
    }
  // 10 % and 16 px each side: between two LED-on frames of a simulated 48-frame sweep (15 deg
  // of azimuth apart, far more than at 30 frames/s) the sheet stayed inside (bench/capture_bench's
  // sweep cases: same samples as with 25 %, which cost 1.5-2x the time); a miss widens it.
  const double mx = growth * (x1 - x0) + 16.0, my = growth * (y1 - y0) + 16.0;
  return PixelRect{static_cast<int>(std::floor(x0 - mx)), static_cast<int>(std::floor(y0 - my)),
                   static_cast<int>(std::ceil(x1 - x0 + 2 * mx)),
                   static_cast<int>(std::ceil(y1 - y0 + 2 * my))};
}

// The markers in view at `pose` (all four corners project into the image): how many, and how
// each maps one tag cell to pixels near its corners 0 and 2 (the columns are the image vectors of
// a cell's two edges; at a grazing view the far edges are shorter than the near ones).
struct MarkersInView {
  int count = 0;
  std::vector<Eigen::Matrix2d> cellMaps;
};

MarkersInView markersInView(const vision::Pose& pose, const vision::CameraModel& camera,
                            const vision::TargetGeometry& target) {
  MarkersInView view;
  for (const vision::Marker& marker : target.markers) {
    std::array<Eigen::Vector2d, 4> px;
    bool inView = true;
    for (int c = 0; c < 4 && inView; ++c) {
      const auto p =
          camera.project(pose.toCamera({marker.cornersMm[c].xMm, marker.cornersMm[c].yMm, 0.0}));
      inView = p && p->x() >= 0 && p->y() >= 0 && p->x() < camera.intrinsics.widthPx &&
               p->y() < camera.intrinsics.heightPx;
      if (inView) px[c] = *p;
    }
    if (!inView) continue;
    ++view.count;
    Eigen::Matrix2d atFirst, atThird;
    atFirst << px[1] - px[0], px[3] - px[0];
    atThird << px[2] - px[3], px[2] - px[1];
    view.cellMaps.push_back(atFirst / vision::kTagBorderCells);
    view.cellMaps.push_back(atThird / vision::kTagBorderCells);
  }
  return view;
}

// The cheapest way to look at markers seen through `cellMaps`. First the library's decimations
// (3, 2, 1.5: quads found coarsely, corners refined at full resolution), the coarsest that leaves
// every cell at least minDecimatedCellPx across in any direction (the smaller singular value of
// the scaled map). Only when none does, binning along one axis (2-4 pixels averaged; the corners
// are refined at that resolution, measured worst corner 0.36 / 0.63 / 0.78 px at 2 / 3 / 4 x 1
// against 0.35 px at full resolution, and binned 4 x 4 the view error grew from 0.017 to 0.11 deg):
// the coarsest that leaves every cell minBinnedCellPx. Else full resolution. Decimation 4 is not
// offered: on a 30 deg frame it missed a tag and put a corner 3.8 px off
// (tests/capture/marker_detector_test.cpp).
DetectionScale trackedScale(const std::vector<Eigen::Matrix2d>& cellMaps,
                            const MarkerDetectorSettings& settings) {
  const auto smallestAcross = [&](double sx, double sy) {
    double smallest = 1e30;
    for (const Eigen::Matrix2d& map : cellMaps) {
      const Eigen::Matrix2d scaled = Eigen::Vector2d(1.0 / sx, 1.0 / sy).asDiagonal() * map;
      smallest = std::min(smallest, Eigen::JacobiSVD<Eigen::Matrix2d>(scaled).singularValues()(1));
    }
    return smallest;
  };
  if (cellMaps.empty()) return {};
  for (const float d : {3.0f, 2.0f, 1.5f})
    if (smallestAcross(d, d) >= settings.minDecimatedCellPx) return {d, 1, 1};
  for (int b = 4; b >= 2; --b)
    for (const auto& [bx, by] : {std::pair{b, 1}, std::pair{1, b}})
      if (smallestAcross(bx, by) >= settings.minBinnedCellPx) return {1.0f, bx, by};
  return {};
}

// The region searched after a miss in the predicted one: the sheet grown by 40 % each side
// (axial 75/75 frame 24 of bench/capture_bench's sweep: the hand's 8 deg roll moved the thin
// foreshortened sheet out of the 10 % band; the whole-frame search found it there).
constexpr double kTrackedGrowth = 0.1, kWidenedGrowth = 0.4;

// The scales a tracked pass may take when the predicted one does not fit the budget, or when a
// finer one is wanted: the library's decimations and binning along either axis.
constexpr std::array<DetectionScale, 10> kScales{{{1.0f, 1, 1},
                                                  {1.5f, 1, 1},
                                                  {1.0f, 2, 1},
                                                  {1.0f, 1, 2},
                                                  {2.0f, 1, 1},
                                                  {1.0f, 3, 1},
                                                  {1.0f, 1, 3},
                                                  {1.0f, 4, 1},
                                                  {1.0f, 1, 4},
                                                  {3.0f, 1, 1}}};

// The smallest extent of any predicted tag cell, in the pixels the library sees at `scale`.
double smallestCellPx(const std::vector<Eigen::Matrix2d>& cellMaps, const DetectionScale& scale) {
  double smallest = std::numeric_limits<double>::infinity();
  const double sx = scale.quadDecimate * scale.binX, sy = scale.quadDecimate * scale.binY;
  for (const Eigen::Matrix2d& map : cellMaps) {
    const Eigen::Matrix2d scaled = Eigen::Vector2d(1.0 / sx, 1.0 / sy).asDiagonal() * map;
    smallest = std::min(smallest, Eigen::JacobiSVD<Eigen::Matrix2d>(scaled).singularValues()(1));
  }
  return smallest;
}

double workOf(const SearchPass& pass) {
  return detectionWorkPx(pass.area.width, pass.area.height, pass.scale);
}

// `area` clamped to the image (empty when nothing of it is inside).
PixelRect clampTo(const PixelRect& area, int width, int height) {
  const int x0 = std::clamp(area.x0, 0, width), y0 = std::clamp(area.y0, 0, height);
  const int x1 = std::clamp(area.x0 + area.width, 0, width);
  const int y1 = std::clamp(area.y0 + area.height, 0, height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

// The whole image at `scale` as the fewest tiles that each fit `budget`, overlapping by
// `overlapPx` so that a tag up to that size lies wholly inside one of them; when it takes more
// than one, a tile of the same size centred in the image comes first (the person aims at the
// target: a sheet in the middle of the frame is found whole by one pass).
std::vector<SearchPass> tiled(int width, int height, const DetectionScale& scale, double budget,
                              int overlapPx) {
  for (int count = 1; count <= 64; ++count)
    for (int ny = 1; ny <= count; ++ny) {
      if (count % ny != 0) continue;
      const int nx = count / ny;
      const int tileW = nx == 1 ? width : (width + (nx - 1) * overlapPx + nx - 1) / nx;
      const int tileH = ny == 1 ? height : (height + (ny - 1) * overlapPx + ny - 1) / ny;
      if (detectionWorkPx(tileW, tileH, scale) > budget) continue;
      std::vector<SearchPass> tiles;
      if (count > 1)
        tiles.push_back({{(width - tileW) / 2, (height - tileH) / 2, tileW, tileH}, scale});
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const int x0 = nx == 1 ? 0 : i * (width - tileW) / (nx - 1);
          const int y0 = ny == 1 ? 0 : j * (height - tileH) / (ny - 1);
          tiles.push_back({{x0, y0, tileW, tileH}, scale});
        }
      return tiles;
    }
  return {};
}

// The sheet's image box seen from `pose`, grown by `growth`, clamped to the image; nullopt when
// it cannot be projected or too little of it (under 16 px either way) is inside.
std::optional<PixelRect> regionInImage(const vision::Pose& pose, const vision::CameraModel& camera,
                                       const vision::RectMm& sheet, double growth) {
  const auto box = sheetRegion(pose, camera, sheet, growth);
  if (!box) return std::nullopt;
  const PixelRect inside = clampTo(*box, camera.intrinsics.widthPx, camera.intrinsics.heightPx);
  if (inside.width < 16 || inside.height < 16) return std::nullopt;
  return inside;
}

// The finest of kScales whose cells seen through `cellMaps` are larger than `than` px and whose
// pass over `area` costs at most `sparePx`.
std::optional<DetectionScale> finestFitting(const std::vector<Eigen::Matrix2d>& cellMaps,
                                            const PixelRect& area, double than, double sparePx) {
  std::optional<DetectionScale> best;
  double bestCell = than;
  for (const DetectionScale& scale : kScales) {
    const double cell = smallestCellPx(cellMaps, scale);
    if (cell > bestCell && workOf({area, scale}) <= sparePx) best = scale, bestCell = cell;
  }
  return best;
}

// One frame's passes: each run on the frame and its work counted against the budget; the markers
// kept are those of the pass that found the most known ones (the later of equals).
class FramePasses {
 public:
  FramePasses(MarkerDetector& detector, const hal::Frame& frame,
              const vision::TargetGeometry& target, double budgetPx)
      : detector_(detector), frame_(frame), target_(target), budgetPx_(budgetPx) {}

  double spare() const { return budgetPx_ - result_.workPx; }
  // Known markers found by the best pass so far; -1 before any pass.
  int bestCount() const { return bestCount_; }

  // Runs `pass` and keeps its markers when they are at least as many as the best so far.
  void run(const SearchPass& pass, bool tracked) {
    std::vector<DetectedMarker> found = detector_.detect(frame_, pass.area, pass.scale);
    ++result_.passes;
    result_.workPx += workOf(pass);
    const int count = countKnown(found, target_);
    if (count < bestCount_) return;
    bestCount_ = count;
    result_.markers = std::move(found);
    result_.trackedScale = tracked ? std::optional(pass.scale) : std::nullopt;
  }

  MarkerSearchResult& result() { return result_; }

 private:
  MarkerDetector& detector_;
  const hal::Frame& frame_;
  const vision::TargetGeometry& target_;
  double budgetPx_;
  MarkerSearchResult result_;
  int bestCount_ = -1;
};

// The tracked passes around `lastPose`: the sheet's predicted region at the predicted scale, then
// finer or wider when markers were lost. True when a pass was wanted but did not fit the budget.
bool runTrackedPasses(FramePasses& passes, const vision::Pose& lastPose,
                      const vision::CameraModel& camera, const vision::TargetGeometry& target,
                      const MarkerDetectorSettings& settings, int minMarkers) {
  const auto predicted = regionInImage(lastPose, camera, target.sheet, kTrackedGrowth);
  if (!predicted) return false;
  const MarkersInView expected = markersInView(lastPose, camera, target);
  const int enough = std::max(minMarkers, (expected.count + 1) / 2);
  // The predicted scale, or when the region is too large for it, the finest that fits.
  std::optional<DetectionScale> scale = trackedScale(expected.cellMaps, settings);
  if (workOf({*predicted, *scale}) > passes.spare())
    scale = finestFitting(expected.cellMaps, *predicted, 0.0, passes.spare());
  if (!scale) return true;
  passes.run({*predicted, *scale}, true);
  const double cell = smallestCellPx(expected.cellMaps, *scale);
  if (passes.bestCount() >= minMarkers && passes.bestCount() < enough) {
    // Markers there, but some lost at this scale: the same region finer, if affordable.
    if (const auto finer = finestFitting(expected.cellMaps, *predicted, cell, passes.spare()))
      passes.run({*predicted, *finer}, true);
  } else if (passes.bestCount() < minMarkers) {
    // The target moved further than predicted: a wider region at the same scale.
    const auto wide = regionInImage(lastPose, camera, target.sheet, kWidenedGrowth);
    if (wide && workOf({*wide, *scale}) <= passes.spare())
      passes.run({*wide, *scale}, true);
    else
      return true;
  }
  return false;
}

// The next passes of the fixed `acquisition` list from `next` on (which it advances), each at most
// once, until `wantedMarkers` are found. True when it stopped at a pass that did not fit the budget.
bool runAcquisitionPasses(FramePasses& passes, const std::vector<SearchPass>& acquisition,
                          std::size_t& next, int wantedMarkers) {
  for (std::size_t tried = 0; passes.bestCount() < wantedMarkers && tried < acquisition.size();
       ++tried) {
    const SearchPass& pass = acquisition[next];
    if (workOf(pass) > passes.spare()) return true;
    passes.run(pass, false);
    next = (next + 1) % acquisition.size();
  }
  return false;
}

}  // namespace

MarkerSearch::MarkerSearch(const vision::TargetGeometry& target, const vision::CameraModel& camera,
                           MarkerDetectorSettings settings, int minMarkers)
    : target_(target),
      camera_(camera),
      settings_(settings),
      minMarkers_(minMarkers),
      detector_(settings) {
  if (settings.trackingPatienceFrames < 0) {
    std::ostringstream message;
    message << "marker search: tracking patience " << settings.trackingPatienceFrames
            << " frames is negative";
    throw CaptureError(message.str());
  }
  // Re-acquisition: binning 4 x 1 first (it finds the tags of a 30 deg view and, unlike the
  // library's decimation, of a 75 deg one, foreshortened along the image's y: measured 15 and 11
  // of 16 tags a frame over bench/capture_bench's sweeps, for the cost of decimation 3, which
  // finds 14 and 0.6), then the settings' decimation, binning the other way (a camera rolled by
  // 90 deg), decimation 1.5, and full resolution for small or far targets. 128 px of overlap: a
  // tag at the rig's 30 cm is under 100 px across.
  // Without a budget (offline) the order that was measured before the budget existed: the
  // settings' decimation, then full resolution (what detect() without a scale does), which
  // keeps `slicecap process`'s frames and view errors as they were.
  const int width = camera.intrinsics.widthPx, height = camera.intrinsics.heightPx;
  if (std::isinf(settings.frameBudgetPx)) {
    acquisition_ = {{{0, 0, width, height}, {settings.decimation, 1, 1}},
                    {{0, 0, width, height}, {1.0f, 1, 1}}};
    return;
  }
  for (const DetectionScale& scale : {DetectionScale{1.0f, 4, 1},
                                      DetectionScale{settings.decimation, 1, 1},
                                      DetectionScale{1.0f, 1, 4}, DetectionScale{1.5f, 1, 1},
                                      DetectionScale{1.0f, 1, 1}})
    for (const SearchPass& pass : tiled(width, height, scale, settings.frameBudgetPx, 128))
      acquisition_.push_back(pass);
}

void MarkerSearch::located(const vision::Pose& pose) {
  trackFrom(pose);
  nextAcquisition_ = 0;
}

void MarkerSearch::trackFrom(const vision::Pose& pose) {
  lastPose_ = pose;
  framesSinceLastPose_ = 0;
}

MarkerSearchResult MarkerSearch::search(const hal::Frame& frame, bool countsAsMiss) {
  if (countsAsMiss && ++framesSinceLastPose_ > settings_.trackingPatienceFrames)
    lastPose_.reset();
  // Without a budget nothing is spread over frames: every frame takes the list from its start
  // (offline, an LED-off frame read ahead would otherwise move the next LED-on frame's start).
  if (std::isinf(settings_.frameBudgetPx)) nextAcquisition_ = 0;
  FramePasses passes(detector_, frame, target_, settings_.frameBudgetPx);
  // A pass was wanted but did not fit this frame's budget.
  bool wanted =
      lastPose_ && runTrackedPasses(passes, *lastPose_, camera_, target_, settings_, minMarkers_);
  // Re-acquisition: the next passes of the fixed list that fit, each at most once per frame, until
  // fullResolutionBelow markers are found (as detect() without a scale: a pose from the first 4
  // found by a coarse pass is less precise; beyond minMarkers only while the budget lasts).
  const int wantedMarkers = passes.bestCount() >= minMarkers_
                                ? 0
                                : std::max(minMarkers_, settings_.fullResolutionBelow);
  if (runAcquisitionPasses(passes, acquisition_, nextAcquisition_, wantedMarkers))
    wanted = passes.bestCount() < minMarkers_;
  MarkerSearchResult result = std::move(passes.result());
  result.deferred = passes.bestCount() < minMarkers_ && wanted;
  if (passes.bestCount() < 0) result.markers.clear();
  return result;
}

}  // namespace slicecap::capture
