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
                  const std::vector<std::uint8_t>& encodeTable, SampleNoise& noise,
                  std::uint16_t* out) {
  const float* ambient = exposure.ambient;
  const float* lit = exposure.lit;
  for (int i = 0; i < widthPx * 3; ++i) {
    const std::size_t at = exposure.base + i;
    const float signal = exposure.ambientScale * ambient[at] + exposure.ledScale * lit[at];
    const float value = noise.added(signal) * gains[i % 3];
    const float clamped = std::min(std::max(value, 0.0f), 1.0f);
    out[at] = encodeTable[static_cast<std::size_t>(clamped * 65535.0f + 0.5f)];
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
