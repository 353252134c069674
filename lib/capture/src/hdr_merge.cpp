// The per-bin HDR merge: clipped and dark cells out, inverse-variance weights, per cell.
#include "slicecap/capture/hdr_merge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slicecap::capture {
namespace {

// One cell's channel over the bin's frames, or its largest reading when every frame clips it.
double mergeCell(const std::vector<const HdrReading*>& readings, std::size_t cell, int channel,
                 bool* clippedEverywhere) {
  bool anyBright = false, anyUsable = false;
  for (const HdrReading* r : readings) {
    const HdrCell& c = r->cells[cell];
    if (c.clipped) continue;
    anyUsable = true;
    anyBright = anyBright || c.level >= kHdrDarkFraction;
  }
  if (!anyUsable) {
    *clippedEverywhere = true;
    double largest = 0.0;
    for (const HdrReading* r : readings)
      largest = std::max(largest, r->cells[cell].radiance[channel]);
    return largest;
  }
  double weighted = 0.0, weights = 0.0, plain = 0.0;
  int count = 0;
  for (const HdrReading* r : readings) {
    const HdrCell& c = r->cells[cell];
    if (c.clipped || (anyBright && c.level < kHdrDarkFraction)) continue;
    // A noise-free reading (variance 0) would take all the weight: floor it far below any real one.
    const double w = 1.0 / std::max(c.variance[channel], std::numeric_limits<double>::min() * 1e10);
    weighted += w * c.radiance[channel];
    weights += w;
    plain += c.radiance[channel];
    ++count;
  }
  return weights > 0 && std::isfinite(weighted / weights) ? weighted / weights : plain / count;
}

}  // namespace

std::optional<HdrMerge> mergeHdrBin(const std::vector<FrameSample>& samples) {
  std::vector<const HdrReading*> readings;
  for (const FrameSample& s : samples) {
    if (!s.hdr || s.hdr->cells.empty()) return std::nullopt;
    if (!readings.empty() && s.hdr->cells.size() != readings.front()->cells.size())
      return std::nullopt;
    readings.push_back(&*s.hdr);
  }
  if (readings.empty()) return std::nullopt;
  HdrMerge merge;
  const std::size_t cells = readings.front()->cells.size();
  Rgb radiance;
  for (std::size_t k = 0; k < cells; ++k) {
    bool clipped = false;
    for (int c = 0; c < 3; ++c)
      radiance[c] += mergeCell(readings, k, c, &clipped) / double(cells);
    merge.clippedCells += clipped ? 1 : 0;
  }
  Rgb irradiance, plainIrradiance;
  double weights = 0.0;
  for (const HdrReading* r : readings) {
    irradiance = irradiance + r->irradiance * r->irradianceWeight;
    plainIrradiance = plainIrradiance + r->irradiance * (1.0 / double(readings.size()));
    weights += r->irradianceWeight;
  }
  irradiance = weights > 0 ? irradiance * (1.0 / weights) : plainIrradiance;
  for (int c = 0; c < 3; ++c)
    merge.value[c] = irradiance[c] > 0 ? std::max(0.0, radiance[c]) / irradiance[c] : 0.0;
  return merge;
}

}  // namespace slicecap::capture
