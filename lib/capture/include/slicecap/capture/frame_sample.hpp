// One accepted frame's measurement for the slice being swept.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::capture {

/// \brief One target cell of the window's sample square in one frame of an HDR sweep.
struct HdrCell {
  Rgb radiance;          ///< per unit exposure x gain, the room light (same level) subtracted
  Rgb variance;          ///< of `radiance`, from the noise model at this frame's exposure
  double level = 0.0;    ///< the reading's brightest channel as exposed, fraction of full scale
  bool clipped = false;  ///< a pixel channel of the cell at or above the clip fraction
};

/// \brief What an HDR sweep's frame keeps for the per-bin merge (hdr_merge.hpp): its window
/// cells (clipped ones too: the merge leaves them out) and its irradiance.
struct HdrReading {
  int exposureLevel = 0;        ///< the recording's frames[].exposure_level (0 = longest)
  std::vector<HdrCell> cells;   ///< kHdrCellsPerSide^2 cells, row by row
  Rgb irradiance;               ///< the point-light fit's at the window centre, per exposure x gain
  double irradianceWeight = 0.0;  ///< ~ inverse relative variance: the references' summed SNR^2
};

/// \brief The window's sample square is read in this many cells per side in HDR sweeps.
inline constexpr int kHdrCellsPerSide = 6;

/// \brief One cell of the window in one frame: a BRDF sample at the cell's own light and view
/// directions (docs/method.md §9, "Window cells").
struct CellSample {
  Direction light;      ///< toward the LED from the cell's centre (target frame, degrees)
  Direction view;       ///< toward the camera from the cell's centre
  Rgb value;            ///< linear BRDF, 1/sr: the room light subtracted, / the irradiance there
  Rgb variance;         ///< of `value`, from the noise model (the irradiance taken as exact)
  bool clipped = false;  ///< a pixel channel at or above the clip fraction, or out of the image
};

/// \brief The whole window of one frame read as cellsPerSide x cellsPerSide cells, with the
/// geometry their directions come from: what the journal stores (the directions are recomputed
/// from it, window_cells.hpp placeCellDirections, so a replayed sample has the same cells).
struct WindowCells {
  int cellsPerSide = 0;
  /// \brief The read part of the window on the target, mm {xMin, yMin, xMax, yMax}: the window
  /// inset by PipelineSettings::windowCellInsetPx at this frame's pose.
  std::array<double, 4> gridMm{};
  std::array<double, 3> lightMm{};   ///< the LED, target frame (mm; origin the window centre)
  std::array<double, 3> cameraMm{};  ///< the camera centre, target frame
  std::vector<CellSample> cells;     ///< cellsPerSide^2, row by row (+y rows, +x within a row)
};

/// \brief What one frame contributes: the BRDF of the window at the frame's actual light and view
/// directions (target frame, degrees), with where it came from.
struct FrameSample {
  std::int64_t timestampUs = 0;  ///< the frame's capture time
  std::uint64_t frameIndex = 0;  ///< position in its recording or stream
  Direction light;               ///< direction to the LED from the window centre
  Direction view;                ///< direction to the camera from the window centre
  Rgb value;                     ///< linear BRDF, 1/sr (HDR: this frame alone, clipped or not)
  std::optional<HdrReading> hdr{};  ///< HDR sweeps only (PipelineSettings::hdr)
  /// \brief The whole window as cells at their own directions (PipelineSettings::
  /// windowCellsPerSide > 0; none in journals written before them). `value` stays the centre's.
  std::optional<WindowCells> cells{};
};

}  // namespace slicecap::capture
