// A slice's bin values from the window cells nearest each bin centre in angle (docs/method.md
// §9, "The slice value from the cells").
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/core/grid.hpp"

namespace slicecap::capture {
namespace {

// Distance of a cell from a pair of directions: the light's and the view's angles together.
double distanceDeg(const CellSample& cell, const Direction& light, const Direction& view) {
  return std::hypot(angleBetweenDeg(cell.light, light), angleBetweenDeg(cell.view, view));
}

// The inverse-variance weighted mean of `cells`, at their weighted mean directions. One weight
// per cell (its channels' mean variance), so a cell's colour is kept.
SliceSample pooled(const std::vector<const CellSample*>& cells) {
  Rgb value;
  UnitVector light{0, 0, 0}, view{0, 0, 0};
  double total = 0.0;
  for (const CellSample* c : cells) {
    // A noise-free reading (variance 0) must not divide by zero: its weight is large and finite.
    const double w = 1.0 / std::max(c->variance.mean(), 1e-30);
    value += w * c->value;
    const UnitVector l = toUnitVector(c->light), v = toUnitVector(c->view);
    light = {light.x + w * l.x, light.y + w * l.y, light.z + w * l.z};
    view = {view.x + w * v.x, view.y + w * v.y, view.z + w * v.z};
    total += w;
  }
  return {toDirection(light), toDirection(view), value * (1.0 / total)};
}

// The slice parameter a cell's own directions give.
double parameterOf(SliceKind kind, const CellSample& cell) {
  return sliceParameterDeg(kind, {cell.light, cell.view, cell.value});
}

// The cell of `cells` nearest in angle to the slice's nominal directions at parameter
// `parameterDeg`, pooled with every cell within `toleranceDeg` of it.
SliceSample nearestAndPooled(const std::vector<const CellSample*>& cells, const SliceId& id,
                             double parameterDeg, double toleranceDeg) {
  const AzimuthPair azimuths = slicePoint(id.kind, parameterDeg);
  const Direction light{double(id.elevations.thetaIDeg), azimuths.phiIDeg};
  const Direction view{double(id.elevations.thetaVDeg), azimuths.phiVDeg};
  const CellSample* nearest = nullptr;
  double best = std::numeric_limits<double>::infinity();
  for (const CellSample* c : cells)
    if (const double d = distanceDeg(*c, light, view); d < best) best = d, nearest = c;
  std::vector<const CellSample*> pool;
  for (const CellSample* c : cells)
    if (distanceDeg(*c, nearest->light, nearest->view) <= toleranceDeg) pool.push_back(c);
  return pooled(pool);
}

}  // namespace

std::vector<std::vector<const CellSample*>> usableCellsByBin(const AzimuthBins& bins,
                                                             SliceKind kind) {
  std::vector<std::vector<const CellSample*>> out(std::size_t(bins.binCount()));
  for (int b = 0; b < bins.binCount(); ++b)
    for (const FrameSample& frame : bins.samplesIn(b)) {
      if (!frame.cells) continue;
      for (const CellSample& cell : frame.cells->cells) {
        if (cell.clipped || !std::isfinite(cell.value.mean())) continue;
        const double parameter = sliceParameterDeg(kind, {cell.light, cell.view, cell.value});
        out[std::size_t(bins.binOf(parameter))].push_back(&cell);
      }
    }
  return out;
}

std::vector<SliceSample> sliceFromCells(const AzimuthBins& bins, const SliceId& id,
                                        const CellSliceRule& rule) {
  if (id.kind == SliceKind::Point)
    throw CaptureError("slice " + toString(id) + ": a point slice has no bins");
  if (!(rule.pointsEveryDeg >= 0.0) || !std::isfinite(rule.pointsEveryDeg))
    throw CaptureError("slice " + toString(id) + ": cells' points every " +
                       std::to_string(rule.pointsEveryDeg) + " deg: not a stretch of the slice");
  const std::vector<std::vector<const CellSample*>> cellsOfBin = usableCellsByBin(bins, id.kind);
  std::vector<SliceSample> out;
  for (int b = 0; b < bins.binCount(); ++b) {
    const std::vector<const CellSample*>& cells = cellsOfBin[std::size_t(b)];
    if (cells.empty()) {
      // No usable cell of any frame falls here: the window centres (a peak clipped in every
      // frame keeps the HDR merge's lower bound; frames from before cells keep their median).
      if (std::optional<SliceSample> centre = bins.combineBin(b)) out.push_back(*centre);
      continue;
    }
    if (rule.pointsEveryDeg > 0.0) {
      // Stretches of the cells' own parameter, in order: a lobe's flanks as well as its top. Each
      // read as a bin is (nearestAndPooled), at its centre's nominal directions, so a sharp peak
      // is not averaged with the flank beside it.
      std::map<long, std::vector<const CellSample*>> stretches;
      for (const CellSample* c : cells)
        stretches[long(std::floor(parameterOf(id.kind, *c) / rule.pointsEveryDeg))].push_back(c);
      for (const auto& [stretch, group] : stretches)
        out.push_back(nearestAndPooled(group, id, (double(stretch) + 0.5) * rule.pointsEveryDeg,
                                       rule.poolToleranceDeg));
      continue;
    }
    out.push_back(nearestAndPooled(cells, id, b * bins.binWidthDeg(), rule.poolToleranceDeg));
  }
  return out;
}

std::vector<FrameCellPoints> cellPointsByFrame(const AzimuthBins& bins, SliceKind kind) {
  std::vector<FrameCellPoints> out;
  for (int b = 0; b < bins.binCount(); ++b)
    for (const FrameSample& frame : bins.samplesIn(b)) {
      if (!frame.cells) continue;
      FrameCellPoints points;
      for (const CellSample& cell : frame.cells->cells)
        if (!cell.clipped && std::isfinite(cell.value.mean()))
          points.push_back({{cell.light, cell.view, cell.value}, cell.variance});
      if (!points.empty()) out.push_back(std::move(points));
    }
  // A bin no usable cell reached keeps its window-centre reading, as sliceFromCells does.
  const std::vector<std::vector<const CellSample*>> cellsOfBin = usableCellsByBin(bins, kind);
  for (int b = 0; b < bins.binCount(); ++b)
    if (cellsOfBin[std::size_t(b)].empty())
      if (std::optional<SliceSample> centre = bins.combineBin(b))
        out.push_back({{*centre, Rgb{}}});
  return out;
}

CellTexture addSweepSlices(SliceSet& set, const SliceId& id, const AzimuthBins& bins,
                           const CellTextureRule& rule, const CellSliceRule& sliceRule) {
  bool anyCells = false;
  for (int b = 0; b < bins.binCount() && !anyCells; ++b)
    for (const FrameSample& frame : bins.samplesIn(b))
      anyCells = anyCells || frame.cells.has_value();
  for (const SliceSample& sample : bins.combine())
    set.add(id, sample);
  if (!anyCells) return {};
  const CellTexture texture = cellTextureOf(bins, rule);
  // Texture the factors do not explain: no cell samples, so the slice's cells' reading is
  // its window centres' (SliceSet::cellReading), the window mean the paper's Method B reads.
  const std::optional<AzimuthBins> cells = cellsAsJudged(bins, texture);
  if (!cells) return texture;
  for (const SliceSample& sample : sliceFromCells(*cells, id, sliceRule))
    set.addCellSample(id, sample);
  for (FrameCellPoints& frame : cellPointsByFrame(*cells, id.kind))
    set.addCellFrame(id, std::move(frame));
  return texture;
}

}  // namespace slicecap::capture
