// The model camera's exposure of one scene row: noisy samples to RAW codes or to 8-bit codes.
#include "model_exposure.hpp"

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
  // Written to vectorise (the daemon's frame loop pays this for every frame on `camera = model`,
  // where a real camera's ISP works in parallel): the noisy, gained, clamped value in 1/65535
  // steps. The noise draws are the ones SampleNoise::added reads, in the same order.
  const std::size_t count = std::size_t(std::max(widthPx, 0)) * 3;
  if (count == 0) return;
  thread_local std::vector<float> rowGains;  // the colour gain of each value of a row
  if (rowGains.size() != count || rowGains[0] != gains[0] || rowGains[1] != gains[1] ||
      rowGains[2] != gains[2]) {
    rowGains.resize(count);
    for (std::size_t k = 0; k < count; ++k) rowGains[k] = gains[k % 3];
  }
  const float ambientScale = exposure.ambientScale, ledScale = exposure.ledScale;
  const float inverseFullWell = noise.inverseFullWell, readVariance = noise.readVariance;
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
      const float value = withNoise(signal, normals[i], inverseFullWell, readVariance) * gain[i];
      // Clamps written as selects (maxss/minss), not std::max/min, which the compiler keeps
      // as branches and so does not vectorise; the values are the same for every finite input.
      const float positive = value > 0.0f ? value : 0.0f;
      const float clamped = positive < 1.0f ? positive : 1.0f;
      linear[i] = static_cast<std::uint16_t>(clamped * 65535.0f + 0.5f);
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
