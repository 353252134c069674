// BTF storage in half floats.
#include "slicecap/btf/btf_texture.hpp"

#include <Imath/half.h>

#include <stdexcept>
#include <string>

#include "slicecap/btf/btf_error.hpp"

namespace slicecap::btf {

BtfTexture::BtfTexture(int resolution) : resolution_(resolution) {
  if (resolution < 1 || resolution > 1024)
    throw BtfError("BTF resolution must be 1 to 1024 texels across, not " +
                   std::to_string(resolution));
  halves_.assign(std::size_t(Abrdf::kDirections) * Abrdf::kDirections * texelCount() * 3, 0);
}

void BtfTexture::setTexel(std::size_t texel, const Abrdf& table) {
  const std::span<const float> values = table.values();
  const std::size_t stride = texelCount() * 3;
  std::uint16_t* out = &halves_[texel * 3];
  // Table order is [light][view][rgb], image order [light][view][texel][rgb].
  for (std::size_t pair = 0; pair < values.size() / 3; ++pair, out += stride)
    for (std::size_t c = 0; c < 3; ++c)
      out[c] = Imath::half(values[3 * pair + c]).bits();
}

void BtfTexture::setRow(int row, std::span<const Abrdf> tables) {
  if (tables.size() != std::size_t(resolution_))
    throw BtfError("BtfTexture::setRow: " + std::to_string(tables.size()) +
                   " tables for a row of " + std::to_string(resolution_));
  const std::size_t pairs = std::size_t(Abrdf::kDirections) * Abrdf::kDirections;
  for (std::size_t pair = 0; pair < pairs; ++pair) {
    std::uint16_t* out = &halves_[(pair * texelCount() + std::size_t(row) * resolution_) * 3];
    for (const Abrdf& table : tables) {
      const float* in = &table.values()[3 * pair];
      for (std::size_t c = 0; c < 3; ++c)
        *out++ = Imath::half(in[c]).bits();
    }
  }
}

Abrdf BtfTexture::texel(std::size_t texel) const {
  Abrdf table;
  std::span<float> values = table.values();
  const std::size_t stride = texelCount() * 3;
  const std::uint16_t* in = &halves_[texel * 3];
  for (std::size_t pair = 0; pair < values.size() / 3; ++pair, in += stride)
    for (std::size_t c = 0; c < 3; ++c) {
      Imath::half h;
      h.setBits(in[c]);
      values[3 * pair + c] = h;
    }
  return table;
}

float BtfTexture::value(int light, int view, std::size_t texel, int channel) const {
  Imath::half h;
  h.setBits(image(light, view)[3 * texel + std::size_t(channel)]);
  return h;
}

Abrdf averageTable(const BtfTexture& texture) {
  Abrdf mean;
  const std::size_t texels = texture.texelCount();
  for (int light = 0; light < Abrdf::kDirections; ++light)
    for (int view = 0; view < Abrdf::kDirections; ++view)
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (std::size_t t = 0; t < texels; ++t)
          sum += texture.value(light, view, t, c);
        mean.channel(light, view, c) = static_cast<float>(sum / double(texels));
      }
  return mean;
}

}  // namespace slicecap::btf
