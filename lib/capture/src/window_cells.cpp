// The geometry of a window's cells: their centres and their own light and view directions.
#include "slicecap/capture/window_cells.hpp"

#include <charconv>
#include <stdexcept>
#include <string>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/core/grid.hpp"

namespace slicecap::capture {

std::array<double, 2> cellCentreMm(const WindowCells& cells, int index) {
  const int n = cells.cellsPerSide;
  const int i = index % n, j = index / n;
  const auto& g = cells.gridMm;
  return {g[0] + (i + 0.5) * (g[2] - g[0]) / n, g[1] + (j + 0.5) * (g[3] - g[1]) / n};
}

void placeCellDirections(WindowCells& cells) {
  const int n = cells.cellsPerSide;
  if (n < 1 || cells.cells.size() != std::size_t(n) * std::size_t(n))
    throw CaptureError("window cells: " + std::to_string(cells.cells.size()) +
                       " cells for " + std::to_string(n) + " per side");
  if (!(cells.lightMm[2] > 0.0) || !(cells.cameraMm[2] > 0.0))
    throw CaptureError("window cells: the light and the camera must be above the target");
  for (int k = 0; k < n * n; ++k) {
    const auto [x, y] = cellCentreMm(cells, k);
    CellSample& cell = cells.cells[std::size_t(k)];
    cell.light = toDirection({cells.lightMm[0] - x, cells.lightMm[1] - y, cells.lightMm[2]});
    cell.view = toDirection({cells.cameraMm[0] - x, cells.cameraMm[1] - y, cells.cameraMm[2]});
  }
}

double cellPrecision(double value) {
  char text[32];
  const std::to_chars_result end = std::to_chars(text, text + sizeof text, float(value));
  double out = value;
  std::from_chars(text, end.ptr, out);
  return out;
}

}  // namespace slicecap::capture
