// The per-bin HDR merge: clipped and dark cells out, inverse-variance weights, per cell; the
// window centre's value from the cells when a sharp lobe curves across the sample square.
#include "slicecap/capture/hdr_merge.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace slicecap::capture {
namespace {

constexpr int kCells = kHdrCellsPerSide * kHdrCellsPerSide;

// One cell's channel merged over the bin's frames, and its variance (infinite when every frame
// clips it: then the value is its largest reading, a lower bound).
struct MergedChannel {
  double value = 0.0, variance = 0.0;
};

double channelsMean(const Rgb& v) { return (v[0] + v[1] + v[2]) / 3.0; }

// The variance of the channels' mean, taking their noise as fully correlated (demosaicing mixes
// neighbouring pixels' channels): the larger bound, so the tests below alarm less on noise.
double channelsMeanVariance(const Rgb& variance) {
  const double sigma =
      (std::sqrt(variance[0]) + std::sqrt(variance[1]) + std::sqrt(variance[2])) / 3.0;
  return sigma * sigma;
}

// The usable readings of a cell (not clipped; not too dark when another frame reads it bright)
// agree within their noise plus kHdrSystematicFraction, and no frame that clips the cell reads
// it brighter (its reading is a lower bound): else the frames see different values (different
// directions inside the bin, on a lobe narrower than the bin) and cannot be averaged.
bool readingsAgree(const std::vector<const HdrCell*>& usable,
                   const std::vector<const HdrCell*>& clipped) {
  double weighted = 0.0, weights = 0.0;
  const auto varianceOf = [](const HdrCell& c) {
    return std::max(channelsMeanVariance(c.variance), std::numeric_limits<double>::min() * 1e10);
  };
  for (const HdrCell* c : usable) {
    weighted += channelsMean(c->radiance) / varianceOf(*c);
    weights += 1.0 / varianceOf(*c);
  }
  const double mean = usable.empty() ? 0.0 : weighted / weights;
  const auto allowance = [&](const HdrCell& c, double value) {
    const double systematic = kHdrSystematicFraction * value;
    return varianceOf(c) + systematic * systematic;
  };
  double chiSquare = 0.0;
  for (const HdrCell* c : usable) {
    const double r = channelsMean(c->radiance) - mean;
    chiSquare += r * r / allowance(*c, mean);
  }
  const double dof = double(usable.size()) - 1.0;
  if (dof > 0 && chiSquare > kHdrCurvatureSigmas * kHdrCurvatureSigmas * dof) return false;
  for (const HdrCell* c : clipped) {
    const double bound = channelsMean(c->radiance);
    if (!usable.empty() && mean < bound - kHdrCurvatureSigmas * std::sqrt(allowance(*c, bound)))
      return false;
  }
  return true;
}

MergedChannel mergeCell(const std::vector<const HdrReading*>& readings,
                        const std::vector<double>& offCentreDeg, std::size_t cell, int channel,
                        bool* clippedEverywhere) {
  bool anyBright = false, anyUsable = false;
  for (const HdrReading* r : readings) {
    const HdrCell& c = r->cells[cell];
    if (c.clipped) continue;
    anyUsable = true;
    anyBright = anyBright || c.level >= kHdrDarkFraction;
  }
  std::vector<const HdrCell*> usable, clipped;
  std::size_t nearest = 0;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const HdrCell& c = readings[i]->cells[cell];
    if (c.clipped) clipped.push_back(&c);
    else if (!(anyBright && c.level < kHdrDarkFraction)) usable.push_back(&c);
    if (std::abs(offCentreDeg[i]) < std::abs(offCentreDeg[nearest])) nearest = i;
  }
  if (!readingsAgree(usable, clipped)) {
    // The frame nearest the bin's centre sees the bin's direction best: its reading alone.
    const HdrCell& c = readings[nearest]->cells[cell];
    if (c.clipped) *clippedEverywhere = true;
    return {c.radiance[channel],
            c.clipped ? std::numeric_limits<double>::infinity() : c.variance[channel]};
  }
  if (!anyUsable) {
    *clippedEverywhere = true;
    double largest = 0.0;
    for (const HdrReading* r : readings)
      largest = std::max(largest, r->cells[cell].radiance[channel]);
    return {largest, std::numeric_limits<double>::infinity()};
  }
  double weighted = 0.0, weights = 0.0, plain = 0.0, plainVariance = 0.0;
  int count = 0;
  for (const HdrCell* c : usable) {
    // A noise-free reading (variance 0) would take all the weight: floor it far below any real one.
    const double w =
        1.0 / std::max(c->variance[channel], std::numeric_limits<double>::min() * 1e10);
    weighted += w * c->radiance[channel];
    weights += w;
    plain += c->radiance[channel];
    plainVariance += c->variance[channel];
    ++count;
  }
  if (weights > 0 && std::isfinite(weighted / weights)) return {weighted / weights, 1.0 / weights};
  return {plain / count, plainVariance / (double(count) * count)};
}

// The weights g with g . cells = the window centre's value of the least-squares quadratic
// surface (1, x, y, x^2, xy, y^2) through the usable cells (row by row, x and y in [-1, 1]), or
// nullopt when too few are usable or one of the four around the centre is not.
std::optional<std::array<double, kCells>> centreWeights(const std::array<bool, kCells>& usable) {
  constexpr int n = kHdrCellsPerSide;
  const int centre = n / 2;
  for (int j : {centre - 1, centre})
    for (int i : {centre - 1, centre})
      if (!usable[j * n + i]) return std::nullopt;
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  std::array<Eigen::Matrix<double, 6, 1>, kCells> rows;
  int count = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) * 2.0 / n - 1.0, y = (j + 0.5) * 2.0 / n - 1.0;
      rows[j * n + i] << 1.0, x, y, x * x, x * y, y * y;
      if (!usable[j * n + i]) continue;
      normal += rows[j * n + i] * rows[j * n + i].transpose();
      ++count;
    }
  if (count < kHdrMinCurveCells) return std::nullopt;
  const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(normal);
  if (lu.rank() < 6) return std::nullopt;
  const Eigen::Matrix<double, 6, 1> first = lu.solve(Eigen::Matrix<double, 6, 1>::Unit(0));
  std::array<double, kCells> g{};
  for (int k = 0; k < kCells; ++k)
    g[k] = usable[k] ? first.dot(rows[k]) : 0.0;
  return g;
}

// The window's radiance from its merged cells: their mean, or, when the usable cells (not
// clipped in every frame) curve across the square by more than noise explains (a lobe narrower
// than the square's spread of directions), the quadratic surface's value at the centre, where
// the frame's light and view directions are.
Rgb windowRadiance(const std::vector<std::array<MergedChannel, 3>>& cells, bool* curved) {
  Rgb mean;
  for (const auto& cell : cells)
    for (int c = 0; c < 3; ++c)
      mean[c] += cell[c].value / double(cells.size());
  *curved = false;
  if (cells.size() != static_cast<std::size_t>(kCells)) return mean;
  std::array<bool, kCells> usable{};
  int usableCount = 0;
  for (int k = 0; k < kCells; ++k) {
    usable[k] = std::isfinite(cells[k][0].variance + cells[k][1].variance + cells[k][2].variance);
    usableCount += usable[k] ? 1 : 0;
  }
  const auto g = centreWeights(usable);
  if (!g) return mean;
  // The centre against the usable cells' mean, on the channels' mean, and the spread noise alone
  // gives their difference (both are linear in the cells).
  Rgb centre;
  double difference = 0.0, differenceVariance = 0.0;
  for (int k = 0; k < kCells; ++k) {
    if (!usable[k]) continue;
    const double m = 1.0 / usableCount, w = (*g)[k] - m;
    double value = 0.0;
    for (int c = 0; c < 3; ++c) {
      centre[c] += (*g)[k] * cells[k][c].value;
      value += cells[k][c].value / 3.0;
    }
    const double variance = channelsMeanVariance(
        {cells[k][0].variance, cells[k][1].variance, cells[k][2].variance});
    difference += w * value;
    differenceVariance += w * w * variance;
  }
  // With a cell clipped in every frame the mean is a lower bound; the surface through the others
  // is then the better estimate whenever it is brighter.
  const bool clippedSome = usableCount < kCells;
  *curved = difference > 0 && clippedSome
                ? centre.mean() > mean.mean()
                : std::abs(difference) > kHdrCurvatureSigmas * std::sqrt(differenceVariance);
  return *curved ? centre : mean;
}

}  // namespace

std::optional<HdrMerge> mergeHdrBin(const std::vector<FrameSample>& samples,
                                    std::vector<double> offCentreDeg) {
  if (offCentreDeg.size() != samples.size()) offCentreDeg.assign(samples.size(), 0.0);
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
  std::vector<std::array<MergedChannel, 3>> merged(cells);
  for (std::size_t k = 0; k < cells; ++k) {
    bool clipped = false;
    for (int c = 0; c < 3; ++c)
      merged[k][c] = mergeCell(readings, offCentreDeg, k, c, &clipped);
    merge.clippedCells += clipped ? 1 : 0;
  }
  const Rgb radiance = windowRadiance(merged, &merge.centreFromCurve);
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
