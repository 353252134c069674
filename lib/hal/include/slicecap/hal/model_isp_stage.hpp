// The camera model's ISP on one processed frame: the colour matrix, the Pi 5's temporal denoise,
// the tone curve with its adaptive stretch, and the stream's YUV coding; and the RAW stream and
// timestamps the model camera takes from its Pi. Public for its tests; ModelCamera is its user.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "slicecap/core/image.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/hal/model_isp.hpp"

namespace slicecap::hal::model_isp {

/// \brief The contrast algorithm's stretch: linear light (0..65535) points (in, out), from
/// (0, 0) to (65535, 65535), as rpi.contrast's computeStretchCurve builds them.
using Stretch = std::vector<std::array<double, 2>>;

/// \brief computeStretchCurve (src/ipa/rpi/controller/rpi/contrast.cpp) with its defaults, from
/// a 256-bin histogram of linear luminance over 0..65535.
Stretch stretchFromHistogram(const std::array<std::uint32_t, 256>& histogram);

/// \brief The noise of a linear value as the sensor makes it (the model's shot and read noise),
/// for the temporal denoise's threshold.
struct NoiseLevel {
  float inverseFullWell = 0.0f;
  float readVariance = 0.0f;
};

/// \brief One camera's ISP state across frames (the previous frame's statistics and output).
class IspStage {
 public:
  IspStage(const ModelIsp& isp, ModelPipeline pipeline, const ToneCurve& tone, NoiseLevel noise);
  /// \brief The ISP of `model`, its noise from the sensor's.
  explicit IspStage(const SensorModel& model);

  /// \brief `image`: 3-channel linear values after the colour gains, 0..65535 (clamped); becomes
  /// the stream's 8-bit R'G'B' (through YCbCr and back when the stream is YUV).
  void process(Image& image);

 private:
  void mixColours(std::vector<std::uint16_t>& samples) const;
  void denoiseTemporally(std::vector<std::uint16_t>& samples);
  void encode(std::vector<std::uint16_t>& samples);
  void rebuildTable();

  ModelIsp isp_;
  bool temporalDenoise_ = false;
  ToneCurve tone_;
  NoiseLevel noise_;
  Stretch stretch_;                    // from the frame before's statistics
  std::vector<std::uint8_t> table_;    // linear 0..65535 -> 8-bit code, stretch then tone
  std::vector<std::uint16_t> previous_;  // the previous frame's denoised linear output
};

/// \brief What ModelCamera::configure takes of RAW: the format granted (nullopt: the processed
/// stream), what validation did said as adjustments, or why camera_raw = on is refused.
struct RawStream {
  std::optional<BayerFormat> granted;
  std::vector<std::string> notes;
  std::string refusal;
};
RawStream rawStreamFor(ModelPipeline pipeline, const std::optional<BayerFormat>& sensor,
                       RawCapture wanted, int widthPx, int heightPx);

/// \brief The sensor's codes (`sensor` bits) as the granted format carries them: a Pi 5's 16-bit
/// words hold them in their top bits ("zero padding at the least significant end").
void toGrantedDepth(const BayerFormat& sensor, const BayerFormat& granted,
                    std::vector<std::uint16_t>& mosaic);

/// \brief One frame's timestamp jitter in whole microseconds: Gaussian of `isp`'s standard
/// deviation, cut at 4 of them (so frames stay in order).
std::int64_t timestampJitterUs(const ModelIsp& isp, std::mt19937_64& random);

/// \brief 8-bit R'G'B' `image` through a YUV420 stream of `encoding` (chroma averaged over 2 x 2,
/// 8-bit codes) and decoded back by toImage as a camera's YUV frame is.
void throughYuv420(Image& image, const YuvEncoding& encoding);

}  // namespace slicecap::hal::model_isp
