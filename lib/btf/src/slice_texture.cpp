// Texture bins: bounded per-bin buffers, per-texel medians.
#include "slicecap/btf/slice_texture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "slicecap/btf/btf_error.hpp"
#include "slicecap/core/angles.hpp"

namespace slicecap::btf {
namespace {

// Median of the finite values among the first `count` of `values` (reordered); NaN if none.
float finiteMedian(float* values, int count) {
  float* end = std::remove_if(values, values + count, [](float v) { return !std::isfinite(v); });
  const auto n = static_cast<int>(end - values);
  if (n == 0) return std::numeric_limits<float>::quiet_NaN();
  std::sort(values, end);
  return n % 2 == 1 ? values[n / 2] : 0.5f * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

std::optional<std::size_t> keepSlot(std::span<const double> keptParametersDeg, double parameterDeg,
                                    double binCentreDeg, int framesPerBin) {
  const auto distance = [binCentreDeg](double p) {
    const double d = wrapDeg360(p - binCentreDeg);
    return std::min(d, 360.0 - d);
  };
  if (static_cast<int>(keptParametersDeg.size()) < framesPerBin) return keptParametersDeg.size();
  if (keptParametersDeg.empty()) return std::nullopt;
  const auto farthest =
      std::max_element(keptParametersDeg.begin(), keptParametersDeg.end(),
                       [&](double a, double b) { return distance(a) < distance(b); });
  if (distance(parameterDeg) < distance(*farthest))
    return static_cast<std::size_t>(farthest - keptParametersDeg.begin());
  return std::nullopt;
}

TextureBin combineBinFrames(std::span<const TextureFrame> frames, std::size_t texelCount) {
  TextureBin bin;
  if (frames.empty()) return bin;
  for (const TextureFrame& f : frames)
    if (f.texels.size() != texelCount * 3)
      throw BtfError("texture bin: a frame of " + std::to_string(f.texels.size()) +
                     " values, expected " + std::to_string(texelCount * 3));
  bin.frames = static_cast<int>(frames.size());
  for (const TextureFrame& f : frames) {
    bin.cameraMm += f.cameraMm / static_cast<double>(frames.size());
    bin.lightMm += f.lightMm / static_cast<double>(frames.size());
  }
  bin.texels.resize(texelCount * 3);
  std::vector<float> values(frames.size());
  for (std::size_t i = 0; i < bin.texels.size(); ++i) {
    for (std::size_t k = 0; k < frames.size(); ++k)
      values[k] = frames[k].texels[i];
    bin.texels[i] = finiteMedian(values.data(), bin.frames);
  }
  return bin;
}

std::size_t SliceTexture::memoryBytes() const {
  std::size_t bytes = 0;
  for (const TextureBin& bin : bins)
    bytes += bin.texels.size() * sizeof(float);
  return bytes;
}

SliceTextureBins::SliceTextureBins(SliceId slice, std::size_t texelCount, int framesPerBin,
                                   double binWidthDeg)
    : slice_(slice),
      texelCount_(texelCount),
      framesPerBin_(framesPerBin),
      binWidthDeg_(binWidthDeg),
      bins_(slice.kind, binWidthDeg) {
  if (framesPerBin < 1)
    throw BtfError("texture bins: frames per bin must be at least 1, not " +
                   std::to_string(framesPerBin));
  if (texelCount == 0) throw BtfError("texture bins: no texels");
  frames_.resize(static_cast<std::size_t>(bins_.binCount()));
}

void SliceTextureBins::add(TextureFrame frame) {
  if (frame.texels.size() != texelCount_ * 3)
    throw BtfError("texture bins: a frame of " + std::to_string(frame.texels.size()) +
                   " values, expected " + std::to_string(texelCount_ * 3));
  const int binIndex = bins_.binOf(frame.sliceParameterDeg);
  std::vector<TextureFrame>& bin = frames_[static_cast<std::size_t>(binIndex)];
  std::vector<double> kept;
  for (const TextureFrame& f : bin)
    kept.push_back(f.sliceParameterDeg);
  const std::optional<std::size_t> slot =
      keepSlot(kept, frame.sliceParameterDeg, binIndex * binWidthDeg_, framesPerBin_);
  if (!slot) return;
  if (*slot == bin.size())
    bin.push_back(std::move(frame));
  else
    bin[*slot] = std::move(frame);
}

int SliceTextureBins::filledCount() const {
  return static_cast<int>(
      std::count_if(frames_.begin(), frames_.end(), [](const auto& b) { return !b.empty(); }));
}

std::size_t SliceTextureBins::memoryBytes() const {
  std::size_t bytes = 0;
  for (const auto& bin : frames_)
    bytes += bin.size() * texelCount_ * 3 * sizeof(float);
  return bytes;
}

SliceTexture SliceTextureBins::combine() const {
  SliceTexture out{slice_, std::vector<TextureBin>(frames_.size())};
  for (std::size_t b = 0; b < frames_.size(); ++b)
    out.bins[b] = combineBinFrames(frames_[b], texelCount_);
  return out;
}

}  // namespace slicecap::btf
