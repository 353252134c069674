// The bins of a sweep to pass again: empty ones, and those whose peak the cells rise toward but
// no window reached (docs/method.md §9.5).
#include "slicecap/capture/pass_again.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/core/grid.hpp"

namespace slicecap::capture {
namespace {

// While a sweep runs, its longest run of empty bins (going round) is still ahead of it: the
// bins of that run, to be left out. Ties: the first run found.
std::vector<bool> aheadOfSweep(const std::vector<bool>& empty) {
  const int n = int(empty.size());
  std::vector<bool> ahead(empty.size(), false);
  int start = -1;  // a filled bin: runs are counted from just after it
  for (int b = 0; b < n; ++b)
    if (!empty[std::size_t(b)]) start = b;
  if (start < 0) return ahead;
  int bestFrom = 0, bestLength = 0;
  for (int k = 1, runFrom = 0, length = 0; k <= n; ++k) {
    const int b = (start + k) % n;
    if (empty[std::size_t(b)]) {
      if (length++ == 0) runFrom = b;
      if (length > bestLength) bestLength = length, bestFrom = runFrom;
    } else {
      length = 0;
    }
  }
  for (int k = 0; k < bestLength; ++k) ahead[std::size_t((bestFrom + k) % n)] = true;
  return ahead;
}

struct Group {
  double sum = 0.0, variance = 0.0;
  int count = 0;
  void add(const CellSample& cell) {
    sum += cell.value.mean();
    variance += cell.variance.mean();
    ++count;
  }
  double mean() const { return sum / count; }
  double varianceOfMean() const { return variance / (double(count) * count); }
};

bool peakNotReached(const std::vector<std::vector<const CellSample*>>& cells, int b,
                    const SliceId& id, double binWidthDeg, const PassAgainRule& rule) {
  const int n = int(cells.size());
  const AzimuthPair azimuths = slicePoint(id.kind, b * binWidthDeg);
  const Direction light{double(id.elevations.thetaIDeg), azimuths.phiIDeg};
  const Direction view{double(id.elevations.thetaVDeg), azimuths.phiVDeg};
  auto distance = [&](const CellSample* c) {
    return std::hypot(angleBetweenDeg(c->light, light), angleBetweenDeg(c->view, view));
  };
  // The reach of the slice value: the bin's own cells (sliceFromCells reads no other).
  double nearestDeg = std::numeric_limits<double>::infinity();
  for (const CellSample* c : cells[std::size_t(b)]) nearestDeg = std::min(nearestDeg, distance(c));
  if (!(nearestDeg > rule.reachedWithinDeg)) return false;
  // The flank may lie partly in a neighbouring bin: the cells behind the edge are taken there too.
  Group edge, behind;
  for (const int offset : {-1, 0, 1}) {
    const int k = (b + offset + n) % n;
    if (offset != 0 && (k == b || (offset == 1 && k == (b + n - 1) % n))) continue;  // under 3 bins: each once
    for (const CellSample* c : cells[std::size_t(k)]) {
      const double beyond = distance(c) - nearestDeg;
      if (beyond <= rule.edgeBandDeg) edge.add(*c);
      else if (beyond >= rule.farFromDeg && beyond <= rule.farToDeg) behind.add(*c);
    }
  }
  if (edge.count == 0 || behind.count == 0) return false;
  const double rise = edge.mean() - behind.mean();
  return edge.mean() >= rule.riseFactor * behind.mean() &&
         rise > rule.noiseSigmas * std::sqrt(edge.varianceOfMean() + behind.varianceOfMean());
}

}  // namespace

std::string toString(PassAgainReason reason) {
  return reason == PassAgainReason::Empty ? "empty" : "peak_not_reached";
}

std::vector<PassAgainBin> binsToPassAgain(const AzimuthBins& bins, const SliceId& id,
                                          SweepProgress progress, const PassAgainRule& rule,
                                          const CellTexture& texture) {
  if (id.kind == SliceKind::Point)
    throw CaptureError("slice " + toString(id) + ": a point slice has no bins");
  if (bins.filledCount() == 0) return {};
  // Emptiness by the cells as read (dividing by a factor leaves a usable cell usable); the peak
  // test by the cells as the texture verdict reads them, none for window centres.
  const std::vector<std::vector<const CellSample*>> cells = usableCellsByBin(bins, id.kind);
  const std::optional<AzimuthBins> judged = cellsAsJudged(bins, texture);
  const std::vector<std::vector<const CellSample*>> evidence =
      judged ? usableCellsByBin(*judged, id.kind)
             : std::vector<std::vector<const CellSample*>>(cells.size());
  std::vector<bool> empty;
  for (int b = 0; b < bins.binCount(); ++b)
    empty.push_back(bins.samplesIn(b).empty() && cells[std::size_t(b)].empty());
  const std::vector<bool> ahead = progress == SweepProgress::Running
                                      ? aheadOfSweep(empty)
                                      : std::vector<bool>(empty.size(), false);
  std::vector<PassAgainBin> out;
  for (int b = 0; b < bins.binCount(); ++b) {
    const double azimuthDeg = b * bins.binWidthDeg();
    if (empty[std::size_t(b)]) {
      if (!ahead[std::size_t(b)]) out.push_back({id, b, azimuthDeg, PassAgainReason::Empty});
    } else if (!evidence[std::size_t(b)].empty() &&
               peakNotReached(evidence, b, id, bins.binWidthDeg(), rule)) {
      out.push_back({id, b, azimuthDeg, PassAgainReason::PeakNotReached});
    }
  }
  return out;
}

}  // namespace slicecap::capture
