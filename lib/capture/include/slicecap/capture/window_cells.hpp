// The window read as cells, each a sample at its own directions (docs/method.md §9, "Window
// cells"), and a slice whose bin values come from the cells nearest each bin centre.
#pragma once

#include <array>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/capture/window_cell_texture.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::capture {

/// \brief The centre of cell `index` (row by row) of `cells`' grid on the target plane, mm.
std::array<double, 2> cellCentreMm(const WindowCells& cells, int index);

/// \brief Sets every cell's light and view direction from the geometry: toward cells.lightMm and
/// cells.cameraMm from the cell's centre. Throws CaptureError when the cell count is
/// not cellsPerSide^2 or the light or the camera is not above the target plane.
void placeCellDirections(WindowCells& cells);

/// \brief `value` rounded to float precision (about 7 significant digits) and back: a cell's
/// value and variance are kept so, the journal writes them in their shortest form (half the
/// digits of a double) and a replayed sample holds the same doubles.
double cellPrecision(double value);

/// \brief How a slice's bin values are taken from the cells (sliceFromCells).
struct CellSliceRule {
  /// \brief Cells whose directions lie within this of the nearest cell's (sqrt of the squared
  /// light and view angles) read the same BRDF value up to the lobe's change over this much, and
  /// are averaged with it (inverse-variance weights) against noise. Under half the distance of
  /// neighbouring cells on the default target (~1.1-1.3 deg: 4-5 mm at 300 mm turns the light and
  /// the view by 0.8-0.9 deg each), so one frame's neighbouring cells are never pooled.
  double poolToleranceDeg = 0.5;
  /// \brief 0: one sample per bin, as above. Over 0: one sample per this many degrees of the
  /// slice parameter instead, each from the cells whose own parameter falls in that stretch,
  /// read as a bin is (the cell nearest the stretch centre's nominal directions, pooled within
  /// poolToleranceDeg): a lobe narrower than a bin is then read on its flanks too, not as a
  /// one-bin spike at the bin centre (docs/method.md §9.4; results/2026-12-06-window-cells.md).
  double pointsEveryDeg = 0.0;
};

/// \brief Every usable cell of the sweep's frames (not clipped, a finite value) in the bin of its
/// own slice parameter for a slice of `kind`, indexed by bin: the binning sliceFromCells and
/// binsToPassAgain share. The pointers refer into `bins`.
std::vector<std::vector<const CellSample*>> usableCellsByBin(const AzimuthBins& bins,
                                                             SliceKind kind);

/// \brief One sample per bin of a sweep of slice `id` from the cells of its frames: every
/// unclipped cell is binned by its own slice parameter; in each bin, the cell nearest in angle to
/// the bin centre's nominal light and view directions (the slice's elevations, slicePoint's
/// azimuths; distance sqrt(light angle^2 + view angle^2)) and the cells within
/// rule.poolToleranceDeg of it give the value, at their mean directions: a bin no frame's centre
/// fell in is filled when a neighbouring frame's cells reach it. A bin where no unclipped cell
/// falls (an HDR peak clipped in every frame; frames from a journal written before cells) keeps
/// AzimuthBins::combine's sample. With rule.pointsEveryDeg over 0, each bin's cells give one
/// sample per that stretch of their own parameter instead (CellSliceRule). Ascending by bin.
/// Throws CaptureError for a point slice or a pointsEveryDeg that is negative or not finite.
std::vector<SliceSample> sliceFromCells(const AzimuthBins& bins, const SliceId& id,
                                        const CellSliceRule& rule = {});

/// \brief Every usable cell (not clipped, a finite value) of the sweep's frames as a point, one
/// group per frame, then a group of the window-centre sample (AzimuthBins::combineBin, variance
/// 0) for each bin no usable cell of a slice of `kind` falls in: what a fit of every cell reads
/// (Slice::cellFrames).
std::vector<FrameCellPoints> cellPointsByFrame(const AzimuthBins& bins, SliceKind kind);

/// \brief Adds the sweep's window-centre samples (AzimuthBins::combine) to `set` as slice `id`'s
/// samples and, when any frame carries cells, its samples from the cells (sliceFromCells) as the
/// slice's cell samples and its cell frames (cellPointsByFrame), as the sweep's texture says
/// (cellTextureOf under `rule`): the cells as read, each divided by its albedo factor, or none
/// (the cells' reading of the slice is then the window centres'). Returns the texture found (framesUsed 0 when no frame carries cells).
CellTexture addSweepSlices(SliceSet& set, const SliceId& id, const AzimuthBins& bins,
                           const CellTextureRule& rule = {},
                           const CellSliceRule& sliceRule = {});

}  // namespace slicecap::capture
