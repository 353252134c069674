// The per-frame detection budget: a lost target costs bounded work per frame, is found again
// within a bounded number of frames, and a frame whose search was cut short says so.
#include "slicecap/capture/marker_search.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"

namespace slicecap::capture {
namespace {

// LED-on frame `index` of an ideal 48-frame axial sweep at `thetaDeg` (7.5 deg apart), moved by
// (dx, dy) pixels (the target aimed elsewhere; the uncovered edge is mid gray), and its pose.
struct View {
  hal::Frame frame;
  vision::Pose pose;
};

View renderView(int thetaDeg, int index, int dx = 0, int dy = 0) {
  const SliceId slice{SliceKind::Axial, {thetaDeg, thetaDeg}};
  sim::RigParams rig = sim::RigParams::ideal();
  rig.readNoise = 0.002;
  const vision::CameraModel camera = vision::defaultSimulatedCamera();
  const vision::TargetGeometry target = vision::defaultTarget();
  const sim::FrameRenderer renderer(camera, target, sim::loadMaterial("satin-red-90"), rig);
  const auto plans = sim::planSweep(slice, 15.0, rig, camera, target);
  const sim::FramePlan& plan = plans[static_cast<std::size_t>(index)];
  const sim::FrameScene lit{{plan.pose}, plan.lightMm, true, 8000.0, 1.0, std::nullopt, 7};
  View view{{renderer.render(lit),
             PixelEncoding::Srgb8,
             {static_cast<std::uint64_t>(index), plan.timestampUs, 8000.0, 1.0, true}},
            plan.pose};
  if (dx != 0 || dy != 0) {
    const Image original = view.frame.image;
    Image& moved = view.frame.image;
    std::fill(moved.samples.begin(), moved.samples.end(), 128);
    for (int y = 0; y < moved.height; ++y)
      for (int x = 0; x < moved.width; ++x) {
        const int sx = x - dx, sy = y - dy;
        if (sx < 0 || sy < 0 || sx >= moved.width || sy >= moved.height) continue;
        for (int c = 0; c < moved.channels; ++c)
          moved.samples[(static_cast<std::size_t>(y) * moved.width + x) * moved.channels + c] =
              original.samples[(static_cast<std::size_t>(sy) * moved.width + sx) *
                                   moved.channels +
                               c];
      }
  }
  return view;
}

hal::Frame blankLike(const hal::Frame& frame) {
  hal::Frame blank = frame;
  std::fill(blank.image.samples.begin(), blank.image.samples.end(), 128);
  return blank;
}

MarkerSearch makeSearch(double budgetPx = MarkerDetectorSettings{}.frameBudgetPx) {
  MarkerDetectorSettings settings;
  settings.frameBudgetPx = budgetPx;
  return MarkerSearch(vision::defaultTarget(), vision::defaultSimulatedCamera(), settings, 4);
}

TEST(MarkerSearch, ReacquisitionPassesEachFitTheBudgetAndCoverTheFrame) {
  const MarkerSearch search = makeSearch();
  const double budget = MarkerDetectorSettings{}.frameBudgetPx;
  const auto& passes = search.acquisitionPasses();
  ASSERT_FALSE(passes.empty());
  // Every scale's tiles together cover every pixel of the 1280 x 720 frame.
  std::vector<int> covered;
  float lastDecimation = -1.0f;
  int lastBinX = -1, lastBinY = -1;
  const auto checkCovered = [&] {
    if (covered.empty()) return;
    EXPECT_EQ(*std::min_element(covered.begin(), covered.end()), 1)
        << "scale " << lastDecimation << " / " << lastBinX << " x " << lastBinY;
  };
  for (const SearchPass& pass : passes) {
    EXPECT_LE(detectionWorkPx(pass.area.width, pass.area.height, pass.scale), budget);
    if (pass.scale.quadDecimate != lastDecimation || pass.scale.binX != lastBinX ||
        pass.scale.binY != lastBinY) {
      checkCovered();
      covered.assign(1280 * 720, 0);
      lastDecimation = pass.scale.quadDecimate, lastBinX = pass.scale.binX,
      lastBinY = pass.scale.binY;
    }
    for (int y = pass.area.y0; y < pass.area.y0 + pass.area.height; ++y)
      for (int x = pass.area.x0; x < pass.area.x0 + pass.area.width; ++x)
        covered[static_cast<std::size_t>(y) * 1280 + x] = 1;
  }
  checkCovered();
  // The last scale is full resolution, in tiles: a whole frame of it would cost ~6 budgets.
  EXPECT_EQ(passes.back().scale.quadDecimate, 1.0f);
  EXPECT_EQ(passes.back().scale.binX * passes.back().scale.binY, 1);
  EXPECT_GT(detectionWorkPx(1280, 720, {}), 4 * budget);
}

TEST(MarkerSearch, ALostTargetCostsAtMostTheBudgetEveryFrameAndIsFoundAgain) {
  for (const int thetaDeg : {30, 75}) {
    SCOPED_TRACE(thetaDeg);
    const double budget = MarkerDetectorSettings{}.frameBudgetPx;
    MarkerSearch search = makeSearch();
    const View first = renderView(thetaDeg, 2);
    search.located(first.pose);
    // The target vanishes (the camera points away): every frame stays in budget and says its
    // search was cut short; after the patience the tracked pose is dropped.
    const hal::Frame blank = blankLike(first.frame);
    for (int i = 0; i < 6; ++i) {
      const MarkerSearchResult result = search.search(blank);
      EXPECT_LE(result.workPx, budget) << "frame " << i;
      EXPECT_GT(result.passes, 0) << "frame " << i;
      EXPECT_TRUE(result.deferred) << "frame " << i;
    }
    EXPECT_FALSE(search.tracking());
    // It comes back far from where it was (moved by a third of the frame): found within the
    // frames one round of the re-acquisition passes takes, never over budget.
    const View back = renderView(thetaDeg, 4, 400, thetaDeg == 30 ? 0 : -200);
    const int bound = static_cast<int>(search.acquisitionPasses().size());
    int frames = 0;
    MarkerSearchResult result;
    do {
      result = search.search(back.frame);
      ++frames;
      EXPECT_LE(result.workPx, budget) << "frame " << frames;
    } while (result.markers.size() < 4 && frames <= bound);
    EXPECT_GE(result.markers.size(), 4u) << "not found again in " << frames << " frames";
    EXPECT_FALSE(result.deferred);
    EXPECT_FALSE(result.trackedScale.has_value()) << "found by re-acquisition, not tracking";
  }
}

TEST(MarkerSearch, TheFirstFrameFindsATargetInTheMiddleOfTheView) {
  // No pose yet: the first pass (binning 4 x 1, the tile in the middle of the frame) finds the
  // sheet of either elevation in one frame.
  for (const int thetaDeg : {30, 75}) {
    SCOPED_TRACE(thetaDeg);
    MarkerSearch search = makeSearch();
    const MarkerSearchResult result = search.search(renderView(thetaDeg, 2).frame);
    EXPECT_GE(result.markers.size(), 12u);
    EXPECT_EQ(result.passes, 1);
    EXPECT_FALSE(result.deferred);
  }
}

TEST(MarkerSearch, ATrackingMissWidensTheRegionBeforeTheWholeFrame) {
  // The target moved out of the predicted region (by 150 px: the thin 75 deg band misses it):
  // the wider region finds it in the same frame, still tracked and in budget.
  const View before = renderView(75, 2);
  const View moved = renderView(75, 2, 0, 150);
  MarkerSearch search = makeSearch();
  search.located(before.pose);
  const MarkerSearchResult result = search.search(moved.frame);
  EXPECT_GE(result.markers.size(), 8u);
  EXPECT_TRUE(result.trackedScale.has_value());
  EXPECT_GE(result.passes, 2) << "the predicted region alone should have missed it";
  EXPECT_LE(result.workPx, MarkerDetectorSettings{}.frameBudgetPx);
}

TEST(MarkerSearch, AnUnlimitedBudgetSearchesEveryPassInOneFrameAndDefersNothing) {
  MarkerSearch search = makeSearch(std::numeric_limits<double>::infinity());
  const hal::Frame blank = blankLike(renderView(30, 2).frame);
  const MarkerSearchResult result = search.search(blank);
  EXPECT_TRUE(result.markers.empty());
  EXPECT_FALSE(result.deferred);
  EXPECT_EQ(result.passes, static_cast<int>(search.acquisitionPasses().size()));
}

TEST(MarkerSearch, RefusesABudgetThatIsNotPositive) {
  for (const double budget : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    SCOPED_TRACE(budget);
    EXPECT_THROW(makeSearch(budget), capture::CaptureError);
  }
}

}  // namespace
}  // namespace slicecap::capture
