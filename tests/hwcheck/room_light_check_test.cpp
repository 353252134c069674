// fitFlicker: a lamp's flicker from the rows of LED-off frames, with the scene's own row-to-row
// structure in the way.
#include "slicecap/hwcheck/room_light_check.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "slicecap/hal/room_flicker.hpp"

namespace slicecap::hwcheck {
namespace {

// `count` frames `periodUs` apart of a scene whose rows differ (a target, a desk), each row
// integrating `flicker` over its own exposure.
std::vector<RowProfile> framesOf(const hal::RoomFlicker& flicker, int count, double periodUs,
                                 double exposureUs, double lineTimeUs = 40.0, int rows = 720) {
  std::vector<RowProfile> frames;
  for (int f = 0; f < count; ++f) {
    RowProfile p;
    p.row0StartUs = 7'000'000.0 + f * periodUs;
    for (int r = 0; r < rows; ++r) {
      const double scene = 0.3 + 0.2 * std::sin(r * 0.05) + (r % 97 < 10 ? 0.3 : 0.0);
      p.rowLevels.push_back(scene * flicker.meanFactor(p.row0StartUs + r * lineTimeUs, exposureUs));
    }
    frames.push_back(std::move(p));
  }
  return frames;
}

TEST(FitFlicker, RecoversFrequencyAndDepthOfTheLightBehindTheExposuresAttenuation) {
  for (const auto& [hz, depth] : {std::pair{100.0, 0.3}, std::pair{120.0, 0.1}, std::pair{99.6, 0.5}}) {
    const hal::RoomFlicker flicker{hz, depth, 0.37};
    // 33.3 ms frames: a 100 Hz flicker's phase moves a third of a period a frame.
    const FlickerFit fit = fitFlicker(framesOf(flicker, 12, 33333.0 + (hz == 120.0 ? 3000 : 0), 2000.0),
                                      40.0, 2000.0);
    ASSERT_TRUE(fit.hz) << hz << ": " << fit.problem;
    EXPECT_NEAR(*fit.hz, hz, 0.2);
    EXPECT_NEAR(fit.depth, depth, 0.02 * depth) << "2 ms shows 0.94 of it; the fit divides that out";
  }
}

TEST(FitFlicker, SteadyLightOrFramesAtOnePhaseGiveNoFrequency) {
  const FlickerFit steady = fitFlicker(framesOf({0.0, 0.0, 0.0}, 12, 33333.0, 2000.0), 40.0, 2000.0);
  EXPECT_FALSE(steady.hz);
  EXPECT_FALSE(steady.problem.empty());
  // 40 ms frames on a 100 Hz flicker: every row is at the same phase in every frame; the scene's
  // rows and the flicker cannot be told apart (and the subtraction does not need them to be).
  const FlickerFit pinned =
      fitFlicker(framesOf({100.0, 0.3, 0.1}, 12, 40000.0, 2000.0), 40.0, 2000.0);
  EXPECT_FALSE(pinned.hz);
  EXPECT_EQ(fitFlicker({}, 40.0, 2000.0).problem, "fewer than 3 LED-off frames");
}

TEST(MainsOfFlicker, NamesTheMainsOfALampsFlicker) {
  EXPECT_EQ(mainsOfFlicker(100.4), 50);
  EXPECT_EQ(mainsOfFlicker(119.0), 60);
  EXPECT_FALSE(mainsOfFlicker(80.0));
}

}  // namespace
}  // namespace slicecap::hwcheck
