// Texture in a sweep's window cells: cells that differ by the material's pattern, not by their
// directions (docs/method.md §9.4, "Textured materials").
#pragma once

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap::capture {

/// \brief What the cells' reading of a sweep does about texture.
enum class CellTextureAction {
  AsRead,            ///< no texture found: each cell's value as read
  AlbedoNormalised,  ///< each cell divided by its albedo factor
  WindowCentres,     ///< texture the factors do not explain: the window centres' reading instead
};

/// \brief "as read", "albedo-normalised", "window centres".
std::string_view toString(CellTextureAction action);

/// \brief The action a command line names: "as-read", "normalise", "centres"; nullopt for
/// anything else.
std::optional<CellTextureAction> parseCellTextureAction(std::string_view text);

/// \brief What a sweep's cells say of the material's texture (cellTextureOf).
struct CellTexture {
  /// \brief Frames whose every cell was usable (not clipped, finite) with some channel clear of
  /// the noise in every cell (CellTextureRule::minCellSnr), the ones measured.
  int framesUsed = 0;
  /// \brief Each cell position's albedo factor, row by row, per channel: the median over the
  /// frames of the cell's value over its frame's mean of cells (1 in a channel with too few
  /// frames measured). Empty when too few frames.
  std::vector<Rgb> albedoFactors;
  /// \brief How far the factors are from 1: the root mean square of their logarithms over the
  /// positions and channels, x 100 (about the spread in percent).
  double spreadPercent = 0.0;
  /// \brief How much of the cells' differences the factors leave: over every two cells of
  /// different positions and frames whose directions lie within CellTextureRule::
  /// matchToleranceDeg (the same BRDF value were the texture a factor), the root of their summed
  /// squared differences with the factors divided out over that as read, x 100 (linear, so a
  /// lobe's bright pairs weigh most); 100 when no two cells share directions.
  double unexplainedPercent = 0.0;
  /// \brief The pairs of cells unexplainedPercent compared.
  std::int64_t matchedPairs = 0;
  int binsMatched = 0;    ///< the bins holding those pairs
  int binsWithCells = 0;  ///< the bins holding a usable cell
  CellTextureAction action = CellTextureAction::AsRead;
  /// \brief One line for a report: "cells: window centres (texture spread 64 %, unexplained
  /// 10 % over 176 cell pairs in 3 of 24 bins)".
  std::string describe() const;
};

/// \brief A report's "cell_texture": the verdict, the figures it rests on and describe()'s line
/// (`process --report` per recording, the daemon export's summary per slice).
nlohmann::json toJson(const CellTexture& texture);

/// \brief When the cells' differences are texture, and when a factor explains them.
struct CellTextureRule {
  /// \brief When set, this action whatever the cells show (the measurement still made and
  /// reported; AlbedoNormalised without factors, too few frames, reads the cells as read).
  std::optional<CellTextureAction> forced;
  /// \brief Frames needed in a channel before it says anything (no channel with as many: the
  /// cells as read).
  int minFrames = 8;
  /// \brief A frame's channel is measured only where every cell reads this many standard
  /// deviations of its noise above zero: a cell in the noise (clamped at 0 where the room
  /// light's subtraction overshoots) is no reading of its spot. A single-exposure sweep metered
  /// for a metal's peak leaves most of its frames there, and read them as texture (spread up to
  /// 5 x on brushed-aluminium's diagonal 75/75) before this.
  double minCellSnr = 5.0;
  /// \brief Texture when spreadPercent exceeds this: plain sharp metals measure 1-3 %, the woven
  /// 63-73 % (docs/results/2026-12-06-window-cells.md).
  double textureSpreadPercent = 10.0;
  /// \brief Two cells are at the same directions within this (sqrt of the light and view
  /// angles squared): CellSliceRule::poolToleranceDeg, the cells sliceFromCells averages.
  double matchToleranceDeg = 0.5;
  /// \brief With texture, the factors are applied when unexplainedPercent is under this and
  /// the pairs lie in at least matchedBinsFraction of the bins with cells (the factor shown to
  /// hold over the sweep, not only where two frames happened to meet); otherwise the window
  /// centres are read instead. 5 %: at the woven's ~65 % spread the factors' residue is then
  /// ~3 %, about the goal's 2 % margin over the window mean (docs/method.md §9.4).
  double unexplainedPercent = 5.0;
  double matchedBinsFraction = 0.5;
};

/// \brief The sweep's texture as its cells show it. Each cell position sees the same spot of
/// the material in every frame (the window is fixed on the target), while its directions move
/// with the frame: a ratio to the frame's mean of cells that stays put over the frames is the
/// material's pattern; one that follows the directions is angular detail, which the median over
/// the frames does not keep. Frames of another cell count than the first are left out; never
/// throws.
CellTexture cellTextureOf(const AzimuthBins& bins, const CellTextureRule& rule = {});

/// \brief A copy of `bins` with every frame's cells divided by `factors` (one per cell
/// position, as CellTexture::albedoFactors), variances by their squares. Throws
/// std::invalid_argument when a frame's cell count is not factors.size().
AzimuthBins withCellsNormalised(const AzimuthBins& bins, const std::vector<Rgb>& factors);

/// \brief The sweep's frames with their cells as `texture` (cellTextureOf of these bins) says
/// they are read: a copy of `bins` (AsRead, or AlbedoNormalised without factors), the copy
/// divided by the albedo factors (AlbedoNormalised), or nullopt (WindowCentres: the cells are
/// no evidence of angular detail). What the slice's cell samples (addSweepSlices) and the bins
/// to pass again (binsToPassAgain) both read, so the two never disagree on a sweep.
std::optional<AzimuthBins> cellsAsJudged(const AzimuthBins& bins, const CellTexture& texture);

}  // namespace slicecap::capture
