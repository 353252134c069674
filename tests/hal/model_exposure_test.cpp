// The model camera's noise deviation looked up by the signal's level (model_exposure::sigmaTable)
// against the exact square root, at every level a frame's signals reach and between levels; and
// exposeRgbRow's codes against the per-sample formula it replaced (the square root per sample,
// clamped to [0, 1], x 65535 rounded), which they match to within one code and the deviation's
// 0.05 % of the sample's noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "model_exposure.hpp"

namespace slicecap::hal::model_exposure {
namespace {

// The sensor model's defaults (SensorModel: 8000 electrons, read noise 0.002) and two extremes:
// read noise alone, and shot noise alone with a small well.
struct Noise {
  float inverseFullWell, readVariance;
};
constexpr Noise kNoises[] = {{1.0f / 8000.0f, 0.002f * 0.002f},
                             {0.0f, 0.01f * 0.01f},
                             {1.0f / 500.0f, 0.0f}};

TEST(ModelExposure, TheLookedUpDeviationIsWithinAFractionOfAPercentOfTheExactOne) {
  for (const Noise& n : kNoises) {
    const float* table = sigmaTable(n.inverseFullWell, n.readVariance)->data();
    double largest = 0.0;
    // Signals from 2^-29 of full scale to 2^19 (clipped 500000 times), 64 a level's width.
    for (double signal = std::ldexp(1.0, -29); signal < std::ldexp(1.0, 19); signal *= 1.0 + 1.0 / 32768.0) {
      const float s = float(signal);
      const double exact = std::sqrt(double(s) * n.inverseFullWell + double(n.readVariance));
      largest = std::max(largest, std::abs(table[sigmaLevel(s)] - exact) / exact);
    }
    EXPECT_LT(largest, 0.0005) << "inverse full well " << n.inverseFullWell;
    EXPECT_GT(largest, 0.0) << "the table is exact: the test would not see a coarser one";
    // Zero, negative and tiny signals read the deviation of a zero signal.
    for (float s : {0.0f, -0.5f, -1e30f, 1e-12f})
      EXPECT_FLOAT_EQ(table[sigmaLevel(s)], std::sqrt(n.readVariance)) << s;
  }
}

// Two model cameras of different sensors on one thread (the tests' and the hardware check's case):
// a frame's noise made for the first keeps the first's deviations when the second's are asked for.
TEST(ModelExposure, AnotherSensorsTableLeavesAFramesNoiseAlone) {
  const SampleNoise first = sampleNoise(8000.0, 0.002);
  const std::vector<float> before(first.sigmas, first.sigmas + kSigmaLevels);
  const SampleNoise second = sampleNoise(500.0, 0.01);
  EXPECT_NE(first.sigmas, second.sigmas);
  EXPECT_NE(before[kSigmaLevels / 2], second.sigmas[kSigmaLevels / 2]) << "the two sensors' tables would not differ";
  EXPECT_TRUE(std::equal(before.begin(), before.end(), first.sigmas));
  // Asked again, the same sensor's table is the one kept, not made anew.
  EXPECT_EQ(sampleNoise(500.0, 0.01).sigmas, second.sigmas);
}

TEST(ModelExposure, RgbCodesAreThePerSampleSquareRootsToWithinOneCode) {
  constexpr int kWidth = 4096;
  std::vector<float> ambient(kWidth * 3), lit(kWidth * 3);
  for (int k = 0; k < kWidth * 3; ++k) {
    ambient[k] = 0.02f * float(k % 61);        // 0 .. 1.2 of full scale over the scales below
    lit[k] = k % 7 == 0 ? 400.0f : 0.0f;       // clipped
  }
  const float gains[3] = {1.9f, 1.0f, 1.6f};
  for (const Noise& n : kNoises) {
    // Draws spanning +-4.5 standard deviations, read across the table's wrap (a table of its
    // own: the model's 2^22 normal draws take a second to make under emulation).
    static const std::vector<float> draws = [] {
      std::vector<float> period(4096), d(kNoiseTableSize);
      for (std::size_t k = 0; k < period.size(); ++k) period[k] = 4.5f * std::sin(0.7f * float(k));
      for (std::size_t k = 0; k < d.size(); ++k) d[k] = period[k % period.size()];
      return d;
    }();
    SampleNoise noise;
    noise.inverseFullWell = n.inverseFullWell;
    noise.readVariance = n.readVariance;
    noise.normals = draws.data();
    noise.sigmaTableKept = sigmaTable(n.inverseFullWell, n.readVariance);
    noise.sigmas = noise.sigmaTableKept->data();
    noise.at = kNoiseTableSize - 1000;
    const std::size_t start = noise.at;
    RowExposure e{ambient.data(), lit.data(), 0, 0.5f, 0.01f};
    std::vector<std::uint16_t> codes(kWidth * 3);
    exposeRgbRow(kWidth, e, gains, noise, codes.data());
    EXPECT_EQ(noise.at, (start + codes.size()) & (kNoiseTableSize - 1));
    int clipped = 0, black = 0;
    for (std::size_t k = 0; k < codes.size(); ++k) {
      const float signal = 0.5f * ambient[k] + 0.01f * lit[k];
      const float normal = noise.normals[(start + k) & (kNoiseTableSize - 1)];
      const double noiseCodes =
          exactSigma(signal, n.inverseFullWell, n.readVariance) * normal * gains[k % 3] * 65535.0;
      const double value = (signal + exactSigma(signal, n.inverseFullWell, n.readVariance) * normal) *
                           gains[k % 3];
      const int expected = int(std::min(std::max(value, 0.0), 1.0) * 65535.0 + 0.5);
      // One code of rounding, and the deviation's 0.05 % of this sample's noise.
      ASSERT_LE(std::abs(int(codes[k]) - expected), 1.0 + 0.0005 * std::abs(noiseCodes))
          << "value " << k << ", signal " << signal;
      clipped += codes[k] == 65535;
      black += codes[k] == 0;
    }
    EXPECT_GT(clipped, 0);
    EXPECT_GT(black, 0);
  }
}

}  // namespace
}  // namespace slicecap::hal::model_exposure
