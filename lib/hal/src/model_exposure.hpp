// The model camera's exposure of one scene row (private to lib/hal): the noise of its samples,
// then the ISP's colour gains and tone curve, or the RAW mosaic's codes and their decoding.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
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

// One sample with its shot-plus-read noise (the two are independent Gaussians, so one standard
// normal draw `normal` scaled by their summed variance). The clamp is a select, not std::max,
// which the compiler keeps as a branch: exposeRgbRow's loop vectorises with it inlined.
inline float withNoise(float signal, float normal, float inverseFullWell, float readVariance) {
  const float shot = signal > 0.0f ? signal : 0.0f;
  return signal + std::sqrt(shot * inverseFullWell + readVariance) * normal;
}

// The noise of one frame's samples: per value one withNoise draw, read from the table at a
// position that runs on from sample to sample.
struct SampleNoise {
  float inverseFullWell = 0.0f;
  float readVariance = 0.0f;
  const float* normals = nullptr;
  std::size_t at = 0;

  float added(float signal) {
    const float value = withNoise(signal, normals[at], inverseFullWell, readVariance);
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
