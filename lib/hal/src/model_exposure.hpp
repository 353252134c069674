// The model camera's exposure of one scene row (private to lib/hal): the noise of its samples,
// then the ISP's colour gains and tone curve, or the RAW mosaic's codes and their decoding.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::hal::model_exposure {

// 2^22 standard normal draws, read from a random offset each frame: per-sample noise for a
// 1280 x 720 frame costs a load, not a Box-Muller, so the model keeps up with 30 fps.
constexpr std::size_t kNoiseTableSize = std::size_t(1) << 22;
const std::vector<float>& normalTable();

/// The scene channel (0 R, 1 G, 2 B) a Bayer order puts at (row parity, column parity).
std::array<std::array<int, 2>, 2> cfaColours(BayerOrder order);

// The standard deviation of a sample's shot-plus-read noise (the two are independent Gaussians,
// so one standard normal draw scaled by their summed variance, sqrt(max(signal, 0) / fullWell +
// read^2)), looked up by the signal's level instead of a square root per sample: under emulation
// (the aarch64 check runs the tests under qemu, which emulates every floating-point operation of
// a vector one element at a time) the square root and the clamps around it were most of a model
// frame's cost. The level is the signal's float bits: its exponent and the top kSigmaMantissaBits
// of its mantissa, so a level spans 2^-9 of its signal and the deviation, which grows at most as
// the square root of the signal, is within 0.05 % of the exact one at every signal (measured by
// ModelExposure.TheLookedUpDeviationIsWithinAFractionOfAPercentOfTheExactOne): about a
// thousandth of the noise's own spread over a frame's million samples. Signals below 2^-30 of full
// scale (zero, and the negative ones, whose shot noise is none) read the deviation of a zero
// signal; those above 2^20 (far beyond clipping) that of 2^20.
constexpr int kSigmaMantissaBits = 9;
constexpr int kSigmaLowestExponent = -30, kSigmaHighestExponent = 20;
constexpr std::size_t kSigmaLevels =
    std::size_t(kSigmaHighestExponent - kSigmaLowestExponent) << kSigmaMantissaBits;

// The level of `signal`'s deviation in a table of kSigmaLevels (integer operations only).
inline std::int32_t sigmaLevel(float signal) {
  constexpr int shift = 23 - kSigmaMantissaBits;
  constexpr std::int32_t lowestBits = (127 + kSigmaLowestExponent) << 23;
  std::int32_t bits;
  std::memcpy(&bits, &signal, sizeof bits);
  // A negative signal's bits are negative: it reads level 0, a zero signal's, as do those below
  // 2^-30 (level 1 starts at 2^-30).
  bits = bits > lowestBits - 1 ? bits : lowestBits - 1;
  const std::int32_t level = ((bits - lowestBits) >> shift) + 1;
  return level < std::int32_t(kSigmaLevels) - 1 ? level : std::int32_t(kSigmaLevels) - 1;
}

// The deviation at every level for a sensor whose shot noise is `inverseFullWell` of the signal
// (as a variance) and whose read noise has `readVariance`: at a level's middle signal (level 0:
// at a zero signal). The last one asked is kept per thread (making one is 2^14 square roots);
// shared, so a frame's SampleNoise keeps its own table however another sensor's is asked for.
std::shared_ptr<const std::vector<float>> sigmaTable(float inverseFullWell, float readVariance);

// The exact deviation (the table's entries and the tests' reference).
inline float exactSigma(float signal, float inverseFullWell, float readVariance) {
  const float shot = signal > 0.0f ? signal : 0.0f;
  return std::sqrt(shot * inverseFullWell + readVariance);
}

// The noise of one frame's samples: per value a normal draw read from the table at a position
// that runs on from sample to sample, scaled by the deviation at the value's level.
struct SampleNoise {
  float inverseFullWell = 0.0f;
  float readVariance = 0.0f;
  const float* normals = nullptr;
  std::shared_ptr<const std::vector<float>> sigmaTableKept;  // what `sigmas` points into
  const float* sigmas = nullptr;  // sigmaTable(inverseFullWell, readVariance)->data()
  std::size_t at = 0;

  float added(float signal) {
    const float value = signal + sigmas[sigmaLevel(signal)] * normals[at];
    at = (at + 1) & (kNoiseTableSize - 1);
    return value;
  }
};

// The RAW stream's codes: offset by the black level, up to the format's largest code.
struct RawCodes {
  int largestCode = 0;
  float blackCode = 0.0f;
  float codeRange = 0.0f;
  std::array<std::array<int, 2>, 2> colours{};  // the scene channel of each cell of the mosaic
};

// The RAW codes of a sensor in `format` whose black level is `blackLevel16` on the 16-bit scale.
RawCodes rawCodesOf(const BayerFormat& format, double blackLevel16);

// A frame's noise (shot: electrons at full scale, 0 none; read: fraction of full scale), its
// draws from the table at position 0 (the caller sets `at`).
SampleNoise sampleNoise(double fullWellElectrons, double readNoise);

// One row of the scene as exposed: the light's rates and the row's exposure to each.
struct RowExposure {
  const float* ambient = nullptr;
  const float* lit = nullptr;
  std::size_t base = 0;  // the row's first value in the scene
  float ambientScale = 0.0f, ledScale = 0.0f;
};

// Scene row `row` of a `widthPx` wide frame into `mosaic` (2 widthPx wide), as RAW codes.
void exposeRawRow(int row, int widthPx, const RowExposure& exposure, const RawCodes& raw,
                  SampleNoise& noise, std::vector<std::uint16_t>& mosaic);

// The row's values through the ISP's colour gains, clamped to full scale, as linear 0..65535
// into `out` at the row's place (model_isp::IspStage takes them from there).
void exposeRgbRow(int widthPx, const RowExposure& exposure, const float (&gains)[3],
                  SampleNoise& noise, std::uint16_t* out);

// The mosaic (2 widthPx x 2 heightPx codes) through the bytes a sensor sends and the decoder a
// real camera's frames go through. Throws what decodeBayer throws.
Image decodedMosaic(const BayerFormat& format, int widthPx, int heightPx, double blackLevel16,
                    const std::vector<std::uint16_t>& mosaic);

}  // namespace slicecap::hal::model_exposure
