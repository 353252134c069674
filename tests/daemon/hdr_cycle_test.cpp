// The live HDR exposure cycle: its levels, the blocks of LED pairs, a frame's level by its
// reported exposure, the shortest level shortened where the window clips, and bad parameters.
#include "slicecap/daemon/hdr_cycle.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "slicecap/daemon/slicecapd_error.hpp"

namespace slicecap::daemon {
namespace {

hal::FrameMetadata takenAt(double exposureUs) {
  hal::FrameMetadata m;
  m.exposureUs = exposureUs;
  return m;
}

TEST(HdrCycle, LevelsStartFromTheSweepsExposureAStepApartAndKeepItsGain) {
  HdrCycle two({3200.0, 2.0}, {.levels = 2});
  EXPECT_EQ(two.levelsUs(), (std::vector<double>{3200.0, 200.0}));
  HdrCycle three({3200.0, 2.0}, {.levels = 3});
  EXPECT_EQ(three.levelsUs(), (std::vector<double>{3200.0, 200.0, 20.0}));  // 12.5: the floor
  // The first switch goes to level 1 with the sweep's gain.
  HdrCycle cycle({3200.0, 2.0}, {.levels = 2, .pairsPerLevel = 1});
  EXPECT_FALSE(cycle.pairStarted());  // the first pair: the level the sweep is at
  const std::optional<hal::ExposureSetting> next = cycle.pairStarted();
  ASSERT_TRUE(next);
  EXPECT_EQ(next->exposureUs, 200.0);
  EXPECT_EQ(next->gain, std::optional(2.0));
}

TEST(HdrCycle, EachLevelHoldsItsBlockOfPairsInTurn) {
  HdrCycle cycle({1600.0, std::nullopt}, {.levels = 3, .pairsPerLevel = 2});
  std::vector<int> levelOfPair;
  for (int pair = 0; pair < 12; ++pair) {
    if (cycle.pairStarted()) {
      EXPECT_EQ(pair % 2, 0) << "a switch in mid-block, pair " << pair;
    }
    levelOfPair.push_back(cycle.requestedLevel());
  }
  EXPECT_EQ(levelOfPair, (std::vector<int>{0, 0, 1, 1, 2, 2, 0, 0, 1, 1, 2, 2}));
}

TEST(HdrCycle, AFrameIsAtTheLevelNearestItsReportedExposure) {
  HdrCycle cycle({3200.0, std::nullopt}, {.levels = 3});
  cycle.accepted(1, {196.0, std::nullopt});  // the camera's line time rounds it
  EXPECT_EQ(cycle.levelsUs()[1], 196.0);
  EXPECT_EQ(cycle.levelOf(takenAt(3190.0)), 0);
  EXPECT_EQ(cycle.levelOf(takenAt(200.0)), 1);
  EXPECT_EQ(cycle.levelOf(takenAt(700.0)), 1);   // nearer 196 than 3200 by ratio
  EXPECT_EQ(cycle.levelOf(takenAt(900.0)), 0);   // nearer 3200
  EXPECT_EQ(cycle.levelOf(takenAt(25.0)), 2);
  // A frame that does not say its exposure is at the level asked for last.
  cycle.pairStarted();
  cycle.pairStarted();
  cycle.pairStarted();
  EXPECT_EQ(cycle.levelOf(takenAt(0.0)), cycle.requestedLevel());
}

TEST(HdrCycle, TheShortestLevelShortensWhereItsOwnFramesClipButNotForOlderOnes) {
  HdrCycle cycle({6400.0, std::nullopt}, {.levels = 2});
  EXPECT_TRUE(cycle.shortestClipped(takenAt(400.0)));
  EXPECT_EQ(cycle.levelsUs()[1], 100.0);
  // Frames at the old 400 us arrive after the change: not a reason to shorten again.
  EXPECT_FALSE(cycle.shortestClipped(takenAt(400.0)));
  EXPECT_EQ(cycle.levelsUs()[1], 100.0);
  EXPECT_TRUE(cycle.shortestClipped(takenAt(100.0)));
  EXPECT_EQ(cycle.levelsUs()[1], 25.0);
  EXPECT_TRUE(cycle.shortestClipped(takenAt(25.0)));
  EXPECT_EQ(cycle.levelsUs()[1], 20.0);  // the floor
  EXPECT_FALSE(cycle.shortestClipped(takenAt(20.0)));
  EXPECT_NE(cycle.summary().find("shortened 3 time(s)"), std::string::npos) << cycle.summary();
  // An old frame still counts as the shortest level's.
  EXPECT_EQ(cycle.levelOf(takenAt(400.0)), 1);
}

TEST(HdrCycle, RefusesParametersItCannotRun) {
  EXPECT_THROW(HdrCycle({3200.0, std::nullopt}, {.levels = 1}), daemon::SlicecapdError);
  EXPECT_THROW(HdrCycle({3200.0, std::nullopt}, {.levels = 4}), daemon::SlicecapdError);
  EXPECT_THROW(HdrCycle({3200.0, std::nullopt}, {.levels = 2, .stepRatio = 1.0}),
               daemon::SlicecapdError);
  EXPECT_THROW(HdrCycle({3200.0, std::nullopt}, {.levels = 2, .pairsPerLevel = 0}),
               daemon::SlicecapdError);
  try {
    HdrCycle({15.0, std::nullopt}, {.levels = 2});
    FAIL() << "no room below 15 us";
  } catch (const daemon::SlicecapdError& error) {
    EXPECT_NE(std::string(error.what()).find("no room for a shorter level"), std::string::npos);
  }
}

// A sweep asks before it starts a cycle (no exception as a jump): the same reason, and none for
// a cycle that runs.
TEST(HdrCycle, RefusalSaysWhatTheConstructorWouldThrow) {
  const std::optional<std::string> why = HdrCycle::refusal({15.0, std::nullopt}, {.levels = 2});
  ASSERT_TRUE(why.has_value());
  try {
    HdrCycle({15.0, std::nullopt}, {.levels = 2});
    FAIL() << "no room below 15 us";
  } catch (const daemon::SlicecapdError& error) {
    EXPECT_EQ(*why, error.what());
  }
  EXPECT_EQ(HdrCycle::refusal({3200.0, std::nullopt}, {.levels = 3}), std::nullopt);
}

}  // namespace
}  // namespace slicecap::daemon
