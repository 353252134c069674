// The model camera's exposure of one scene row: noisy samples to RAW codes or to 8-bit codes.
#include "model_exposure.hpp"

#include <cstring>
#include <random>

namespace slicecap::hal::model_exposure {

const std::vector<float>& normalTable() {
  static const std::vector<float> table = [] {
    std::mt19937_64 random(20261202);
    std::normal_distribution<float> normal;
    std::vector<float> values(kNoiseTableSize);
    for (float& v : values) v = normal(random);
    return values;
  }();
  return table;
}

std::shared_ptr<const std::vector<float>> sigmaTable(float inverseFullWell, float readVariance) {
  struct Kept {
    float inverseFullWell = -1.0f, readVariance = -1.0f;
    std::shared_ptr<const std::vector<float>> sigmas;
  };
  thread_local Kept kept;
  if (kept.sigmas && kept.inverseFullWell == inverseFullWell && kept.readVariance == readVariance)
    return kept.sigmas;
  auto sigmas = std::make_shared<std::vector<float>>(kSigmaLevels);
  (*sigmas)[0] = exactSigma(0.0f, inverseFullWell, readVariance);
  for (std::size_t level = 1; level < kSigmaLevels; ++level) {
    // Level k >= 1 spans [2^(e0 + m), 2^(e0 + m) (1 + 2^-9)) with m = (k - 1) / 2^9 in steps
    // of 2^-9 of the octave: its middle signal.
    const double start = std::ldexp(1.0 + double((level - 1) & ((1u << kSigmaMantissaBits) - 1)) /
                                              (1u << kSigmaMantissaBits),
                                    kSigmaLowestExponent + int((level - 1) >> kSigmaMantissaBits));
    const double middle = start * (1.0 + 0.5 / (1u << kSigmaMantissaBits));
    (*sigmas)[level] = float(std::sqrt(middle * inverseFullWell + double(readVariance)));
  }
  // A new table, never the old one rewritten: a SampleNoise made before holds the old one.
  kept = {inverseFullWell, readVariance, std::move(sigmas)};
  return kept.sigmas;
}

std::array<std::array<int, 2>, 2> cfaColours(BayerOrder order) {
  switch (order) {
    case BayerOrder::Rggb: return {{{0, 1}, {1, 2}}};
    case BayerOrder::Grbg: return {{{1, 0}, {2, 1}}};
    case BayerOrder::Gbrg: return {{{1, 2}, {0, 1}}};
    case BayerOrder::Bggr: return {{{2, 1}, {1, 0}}};
  }
  return {{{0, 1}, {1, 2}}};
}

RawCodes rawCodesOf(const BayerFormat& format, double blackLevel16) {
  RawCodes codes;
  codes.largestCode = (1 << format.bitDepth) - 1;
  codes.blackCode = float(std::ldexp(blackLevel16, format.bitDepth - 16));
  codes.codeRange = float(codes.largestCode) - codes.blackCode;
  codes.colours = cfaColours(format.order);
  return codes;
}

SampleNoise sampleNoise(double fullWellElectrons, double readNoise) {
  SampleNoise noise;
  noise.inverseFullWell = fullWellElectrons > 0 ? float(1.0 / fullWellElectrons) : 0.0f;
  noise.readVariance = float(readNoise * readNoise);
  noise.normals = normalTable().data();
  noise.sigmaTableKept = sigmaTable(noise.inverseFullWell, noise.readVariance);
  noise.sigmas = noise.sigmaTableKept->data();
  return noise;
}

// Mosaic rows 2 row and 2 row + 1 are this scene row's cells (read out together, as a sensor's
// 2 x 2 binned mode reads them).
void exposeRawRow(int row, int widthPx, const RowExposure& exposure, const RawCodes& raw,
                  SampleNoise& noise, std::vector<std::uint16_t>& mosaic) {
  const float* ambient = exposure.ambient;
  const float* lit = exposure.lit;
  for (int dy = 0; dy < 2; ++dy) {
    std::uint16_t* codes = mosaic.data() + std::size_t(2 * row + dy) * 2 * widthPx;
    for (int mx = 0; mx < 2 * widthPx; ++mx) {
      const std::size_t at = exposure.base + std::size_t(mx / 2) * 3 + raw.colours[dy][mx & 1];
      const float signal = exposure.ambientScale * ambient[at] + exposure.ledScale * lit[at];
      const float value = noise.added(signal);
      const float code = raw.blackCode + value * raw.codeRange;
      codes[mx] = static_cast<std::uint16_t>(
          std::min(std::max(code, 0.0f), float(raw.largestCode)) + 0.5f);
    }
  }
}

void exposeRgbRow(int widthPx, const RowExposure& exposure, const float (&gains)[3],
                  SampleNoise& noise, std::uint16_t* out) {
  // The daemon's frame loop pays this for every frame on `camera = model` (a real camera's ISP
  // works in parallel), and the tests under qemu pay it per floating-point operation and element
  // (qemu emulates each, vector or not, by a call into its soft-float library): 4 a value here,
  // where the square root per sample, the NaN-careful clamps and the float-to-integer conversion
  // made about 15 (GCC 12, -O2). The deviation is a table look-up (no vector gather on NEON or
  // SSE2, so the loop is scalar: as fast natively as the vectorised one with its square roots).
  // The noisy, gained, clamped value in 1/65535 steps; the noise draws are the ones
  // SampleNoise::added reads, in the same order, scaled by the same deviation.
  const std::size_t count = std::size_t(std::max(widthPx, 0)) * 3;
  if (count == 0) return;
  thread_local std::vector<float> rowGains;  // the colour gain of each value of a row, x 65535
  if (rowGains.size() != count || rowGains[0] != gains[0] * 65535.0f ||
      rowGains[1] != gains[1] * 65535.0f || rowGains[2] != gains[2] * 65535.0f) {
    rowGains.resize(count);
    for (std::size_t k = 0; k < count; ++k) rowGains[k] = gains[k % 3] * 65535.0f;
  }
  const float ambientScale = exposure.ambientScale, ledScale = exposure.ledScale;
  const float* __restrict sigmas = noise.sigmas;
  std::size_t done = 0;
  while (done < count) {
    // The run of draws up to the table's end (it wraps to its start, as added() does).
    const std::size_t run = std::min(count - done, kNoiseTableSize - noise.at);
    const float* __restrict normals = noise.normals + noise.at;
    const float* __restrict ambient = exposure.ambient + exposure.base + done;
    const float* __restrict lit = exposure.lit + exposure.base + done;
    const float* __restrict gain = rowGains.data() + done;
    std::uint16_t* __restrict linear = out + exposure.base + done;
    for (std::size_t i = 0; i < run; ++i) {
      const float signal = ambientScale * ambient[i] + ledScale * lit[i];
      const float value = signal + sigmas[sigmaLevel(signal)] * normals[i];
      // Gained, in 1/65535 steps, rounded to the nearest whole step by adding 1.5 x 2^23 (a float
      // of that size has no fraction bits: the sum's low bits are the rounded code) instead of a
      // float-to-integer conversion, which qemu emulates with a change of rounding mode around
      // it; clamped as an integer: a positive float's bits grow with it, so every sum above the
      // code 65535's reads 65535 (a NaN reads 0), and a sum below the magic number (a negative code,
      // or a negative float, whose bits are negative) reads 0. Exact for |code| < 2^22; halves
      // round to even where they rounded up before (one code at exact ties only).
      constexpr float kMagic = 12582912.0f;  // 1.5 x 2^23
      constexpr std::int32_t kMagicBits = 0x4B400000;
      const float sum = value * gain[i] + kMagic;
      std::int32_t bits;
      std::memcpy(&bits, &sum, sizeof bits);
      // A NaN (whose sign differs: x86 makes -NaN, aarch64 +NaN) reads 0 on both.
      const bool nan = (bits & 0x7fffffff) > 0x7f800000;
      const std::int32_t low = bits > kMagicBits && !nan ? bits : kMagicBits;
      const std::int32_t code = (low < kMagicBits + 65535 ? low : kMagicBits + 65535) - kMagicBits;
      linear[i] = static_cast<std::uint16_t>(code);
    }
    done += run;
    noise.at = (noise.at + run) & (kNoiseTableSize - 1);
  }
}

Image decodedMosaic(const BayerFormat& format, int widthPx, int heightPx, double blackLevel16,
                    const std::vector<std::uint16_t>& mosaic) {
  BayerFrameView view;
  view.format = format;
  view.widthPx = 2 * widthPx;
  view.heightPx = 2 * heightPx;
  const std::vector<std::uint8_t> bytes = packBayer(view.format, view.widthPx, view.heightPx, mosaic);
  view.bytes = bytes;
  view.strideBytes = minimalBayerStrideBytes(view.format, view.widthPx);
  return decodeBayer(view, BayerBlackLevels::uniform(blackLevel16));
}

}  // namespace slicecap::hal::model_exposure
