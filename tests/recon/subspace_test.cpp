// Subspace resampling: the fused elevation blends against the two steps they replace.
#include "slicecap/recon/subspace.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <stdexcept>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

constexpr std::array<int, 6> kElevationsDeg{0, 15, 30, 45, 60, 75};

Subspace randomBlock(ElevationPair pair, std::mt19937& rng) {
  std::uniform_real_distribution<double> value(-2.0, 3.0);
  Subspace block(pair);
  for (int p = 0; p < block.lightRing().count; ++p) {
    for (int q = 0; q < block.viewRing().count; ++q)
      block.at(p, q) = {value(rng), value(rng), value(rng)};
  }
  return block;
}

void expectSameBits(const Subspace& got, const Subspace& expected) {
  ASSERT_EQ(got.elevations(), expected.elevations());
  for (int p = 0; p < got.lightRing().count; ++p) {
    for (int q = 0; q < got.viewRing().count; ++q)
      ASSERT_EQ(got.at(p, q), expected.at(p, q)) << p << ", " << q;
  }
}

// Method B and the prior's residual field call the fused form for every unmeasured pair; it must
// be the blend of the resampled blocks exactly, to the pole and between rings of any size.
TEST(Subspace, ElevationBlendsEqualBlendingTheResampledBlocks) {
  std::mt19937 rng(7);
  for (int fixedDeg : {30, 75}) {
    const Subspace viewLow = randomBlock({fixedDeg, 30}, rng);
    const Subspace viewHigh = randomBlock({fixedDeg, 75}, rng);
    const Subspace lightLow = randomBlock({30, fixedDeg}, rng);
    const Subspace lightHigh = randomBlock({75, fixedDeg}, rng);
    for (int targetDeg : kElevationsDeg) {
      for (double t : {0.0, 0.37, 1.0}) {
        expectSameBits(Subspace::blendAtViewElevation(viewLow, viewHigh, t, targetDeg),
                       Subspace::blend(viewLow.resampledToViewElevation(targetDeg),
                                       viewHigh.resampledToViewElevation(targetDeg), t));
        expectSameBits(Subspace::blendAtLightElevation(lightLow, lightHigh, t, targetDeg),
                       Subspace::blend(lightLow.resampledToLightElevation(targetDeg),
                                       lightHigh.resampledToLightElevation(targetDeg), t));
      }
    }
  }
}

TEST(Subspace, ElevationBlendsRefuseBlocksOfDifferentLines) {
  std::mt19937 rng(3);
  const Subspace a = randomBlock({30, 30}, rng);
  const Subspace b = randomBlock({75, 75}, rng);
  EXPECT_THROW(Subspace::blendAtViewElevation(a, b, 0.5, 45), recon::ReconArgumentError);
  EXPECT_THROW(Subspace::blendAtLightElevation(a, b, 0.5, 45), recon::ReconArgumentError);
}

}  // namespace
}  // namespace slicecap::recon
