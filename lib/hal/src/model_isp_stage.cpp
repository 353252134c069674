// The camera model's ISP on one processed frame: colour matrix, temporal denoise, the adaptive
// tone curve and the YUV stream.
#include "slicecap/hal/model_isp_stage.hpp"

#include <algorithm>
#include <cmath>

#include "slicecap/hal/raw_frame.hpp"

namespace slicecap::hal::model_isp {

namespace {

constexpr double kFull = 65535.0;

bool isIdentity(const std::array<double, 9>& m) {
  return m == std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1};
}

// The histogram's quantile q, in linear 0..65535, interpolated within its bin (libcamera's
// Histogram::quantile).
double quantile(const std::array<std::uint32_t, 256>& histogram, double q) {
  std::uint64_t total = 0;
  for (std::uint32_t n : histogram) total += n;
  if (total == 0) return 0.0;
  const double wanted = q * double(total);
  double below = 0.0;
  for (std::size_t bin = 0; bin < histogram.size(); ++bin) {
    if (below + histogram[bin] > wanted && histogram[bin] > 0)
      return (double(bin) + (wanted - below) / histogram[bin]) * 256.0;
    below += histogram[bin];
  }
  return kFull;
}

double applyStretch(const Stretch& stretch, double x) {
  for (std::size_t i = 1; i < stretch.size(); ++i) {
    const auto& [x0, y0] = stretch[i - 1];
    const auto& [x1, y1] = stretch[i];
    if (x <= x1) return x1 > x0 ? y0 + (x - x0) * (y1 - y0) / (x1 - x0) : y1;
  }
  return x;
}

}  // namespace

Stretch stretchFromHistogram(const std::array<std::uint32_t, 256>& histogram) {
  // contrast.cpp's defaults (Contrast::read): lo_histogram 0.01, lo_level 0.015, lo_max 500,
  // hi_histogram 0.95, hi_level 0.95, hi_max 2000; the IMX708 tuning files set none of them.
  const double levelLo = 0.015 * 65536, levelHi = 0.95 * 65536;
  const double histLo =
      std::max(levelLo, std::min(kFull, std::min(quantile(histogram, 0.01), levelLo + 500)));
  const double mid = quantile(histogram, 0.5);
  const double histHi =
      std::min(levelHi, std::max(0.0, std::max(quantile(histogram, 0.95), levelHi - 2000)));
  // Points out of order (a histogram whose median lies outside lo..hi) are dropped, as
  // libcamera's Pwl::append drops a point that does not move right.
  Stretch stretch{{0.0, 0.0}};
  for (const std::array<double, 2>& point :
       {std::array{histLo, levelLo}, std::array{mid, mid}, std::array{histHi, levelHi},
        std::array{kFull, kFull}})
    if (point[0] > stretch.back()[0] + 1e-6) stretch.push_back(point);
  return stretch;
}

IspStage::IspStage(const ModelIsp& isp, ModelPipeline pipeline, const ToneCurve& tone,
                   NoiseLevel noise)
    : isp_(isp),
      temporalDenoise_(pipeline == ModelPipeline::PiSp && isp.temporalDenoiseWeight > 0.0),
      tone_(tone),
      noise_(noise),
      stretch_{{0.0, 0.0}, {kFull, kFull}} {
  rebuildTable();
}

IspStage::IspStage(const SensorModel& model)
    : IspStage(model.isp, model.pipeline, model.tone,
               NoiseLevel{model.fullWellElectrons > 0 ? float(1.0 / model.fullWellElectrons) : 0.0f,
                          float(model.readNoise * model.readNoise)}) {}

void IspStage::rebuildTable() {
  table_.resize(65536);
  for (std::size_t i = 0; i < table_.size(); ++i)
    table_[i] = static_cast<std::uint8_t>(
        std::lround(255.0 * tone_.encode(applyStretch(stretch_, double(i)) / kFull)));
}

void IspStage::mixColours(std::vector<std::uint16_t>& samples) const {
  const std::array<double, 9>& d = isp_.colourMatrix;
  const float m[9] = {float(d[0]), float(d[1]), float(d[2]), float(d[3]), float(d[4]),
                      float(d[5]), float(d[6]), float(d[7]), float(d[8])};
  // Clamped as integers (conditional moves): a float clamp kept its branches, which the
  // mixed signs of a noisy frame mispredict (28 ms a 720p frame).
  const auto code = [](float v) {
    const int rounded = static_cast<int>(v + 0.5f);  // a negative rounds toward 0: clamped anyway
    return static_cast<std::uint16_t>(std::clamp(rounded, 0, 65535));
  };
  std::uint16_t* __restrict p = samples.data();
  const std::size_t pixels = samples.size() / 3;
  for (std::size_t k = 0; k < pixels; ++k, p += 3) {
    const float r = p[0], g = p[1], b = p[2];
    p[0] = code(m[0] * r + m[1] * g + m[2] * b);
    p[1] = code(m[3] * r + m[4] * g + m[5] * b);
    p[2] = code(m[6] * r + m[7] * g + m[8] * b);
  }
}

// Where the frame is still (its difference from the previous output within the noise) the
// previous output is blended in; where it moved (or the LED switched) the frame passes. A pixel
// the LED lights by less than its noise is blended with the other LED state.
void IspStage::denoiseTemporally(std::vector<std::uint16_t>& samples) {
  if (previous_.size() == samples.size()) {
    // |now - before| <= deviation * sigma(now), squared: sigma^2 = 65535 now / fullWell +
    // 65535^2 readVariance is linear in `now`, so the test needs no square root or division, and
    // the loop has no branch (a blend weight of 0 where the pixel moved). Two thirds of a
    // hardware check's time on the model went to the per-sample sqrt and divide before.
    const float weight = float(isp_.temporalDenoiseWeight);
    const float deviation2 = float(isp_.temporalDenoiseDeviation * isp_.temporalDenoiseDeviation);
    const float perLevel = deviation2 * 65535.0f * noise_.inverseFullWell;
    const float floor = deviation2 * 65535.0f * 65535.0f * noise_.readVariance;
    std::uint16_t* __restrict out = samples.data();
    const std::uint16_t* __restrict before = previous_.data();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const float now = out[i], difference = float(before[i]) - now;
      const bool still = difference * difference <= perLevel * now + floor;
      // `now` is a whole number: unblended, the conversion gives it back unchanged.
      out[i] = static_cast<std::uint16_t>(now + (still ? weight * difference + 0.5f : 0.0f));
    }
  }
  previous_ = samples;
}

void IspStage::encode(std::vector<std::uint16_t>& samples) {
  std::array<std::uint32_t, 256> histogram{};
  if (isp_.adaptiveContrast)
    for (std::size_t i = 0; i + 2 < samples.size(); i += 3) {
      // Rec.709 luminance in 1/256ths (54, 183, 19): a 16-bit value's top byte is its bin.
      const std::uint32_t y = (54u * samples[i] + 183u * samples[i + 1] + 19u * samples[i + 2]) >> 16;
      ++histogram[std::min<std::uint32_t>(255u, y)];
    }
  for (std::uint16_t& v : samples) v = table_[v];
  // This frame's statistics set the curve of the frames after it (the IPA runs on a frame's
  // statistics after the ISP has processed it).
  if (isp_.adaptiveContrast) {
    Stretch next = stretchFromHistogram(histogram);
    if (next != stretch_) {
      stretch_ = std::move(next);
      rebuildTable();
    }
  }
}

void IspStage::process(Image& image) {
  if (!isIdentity(isp_.colourMatrix)) mixColours(image.samples);
  if (temporalDenoise_) denoiseTemporally(image.samples);
  encode(image.samples);
  if (isp_.yuvStream) throughYuv420(image, *isp_.yuvStream);
}

RawStream rawStreamFor(ModelPipeline pipeline, const std::optional<BayerFormat>& sensor,
                       RawCapture wanted, int widthPx, int heightPx) {
  RawStream stream;
  if (wanted == RawCapture::On && !sensor) {
    stream.refusal = "camera_raw = on, but the model offers no RAW stream";
    return stream;
  }
  if (!sensor || wanted == RawCapture::Off) return stream;
  const RawStreamChoice choice = negotiateModelRaw(pipeline, *sensor, widthPx, heightPx);
  if (choice.format.empty()) {
    if (wanted == RawCapture::On) stream.refusal = "camera_raw = on, but " + choice.reason;
    else stream.notes.push_back(choice.reason);
    return stream;
  }
  for (const std::string& note : choice.notes) stream.notes.push_back("RAW " + note);
  stream.granted = bayerFormatFromLibcameraName(choice.format);
  return stream;
}

void toGrantedDepth(const BayerFormat& sensor, const BayerFormat& granted,
                    std::vector<std::uint16_t>& mosaic) {
  const int shift = granted.bitDepth - sensor.bitDepth;
  if (shift > 0)
    for (std::uint16_t& code : mosaic) code = static_cast<std::uint16_t>(code << shift);
}

std::int64_t timestampJitterUs(const ModelIsp& isp, std::mt19937_64& random) {
  if (isp.timestampJitterUs <= 0.0) return 0;
  const double sigma = isp.timestampJitterUs;
  return std::llround(
      std::clamp(sigma * std::normal_distribution<double>()(random), -4.0 * sigma, 4.0 * sigma));
}

void throughYuv420(Image& image, const YuvEncoding& encoding) {
  const int width = image.width, height = image.height;
  const int chromaWidth = (width + 1) / 2, chromaHeight = (height + 1) / 2;
  double kr = 0.299, kb = 0.114;
  if (encoding.matrix == YcbcrMatrix::Rec709) kr = 0.2126, kb = 0.0722;
  if (encoding.matrix == YcbcrMatrix::Rec2020) kr = 0.2627, kb = 0.0593;
  const double kg = 1.0 - kr - kb;
  const bool limited = encoding.range == YuvRange::Limited;
  const double yScale = limited ? 219.0 : 255.0, yOffset = limited ? 16.0 : 0.0;
  const double cScale = limited ? 224.0 : 255.0;
  std::vector<std::uint8_t> luma(std::size_t(width) * height);
  std::vector<double> cb(std::size_t(chromaWidth) * chromaHeight), cr(cb.size());
  std::vector<int> counts(cb.size());
  const auto code = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double r = image.at(x, y, 0) / 255.0, g = image.at(x, y, 1) / 255.0,
                   b = image.at(x, y, 2) / 255.0;
      const double ey = kr * r + kg * g + kb * b;
      luma[std::size_t(y) * width + x] = code(yOffset + yScale * ey);
      const std::size_t c = std::size_t(y / 2) * chromaWidth + x / 2;
      cb[c] += (b - ey) / (2.0 * (1.0 - kb));
      cr[c] += (r - ey) / (2.0 * (1.0 - kr));
      ++counts[c];
    }
  std::vector<std::uint8_t> u(cb.size()), v(cb.size());
  for (std::size_t c = 0; c < cb.size(); ++c) {
    u[c] = code(128.0 + cScale * cb[c] / counts[c]);
    v[c] = code(128.0 + cScale * cr[c] / counts[c]);
  }
  RawFrameView view;
  view.layout = RawLayout::Yuv420;
  view.widthPx = width;
  view.heightPx = height;
  view.planes[0] = luma;
  view.planes[1] = u;
  view.planes[2] = v;
  view.strideBytes[0] = std::size_t(width);
  view.strideBytes[1] = view.strideBytes[2] = std::size_t(chromaWidth);
  view.yuv = encoding;
  image = toImage(view);
}

}  // namespace slicecap::hal::model_isp
