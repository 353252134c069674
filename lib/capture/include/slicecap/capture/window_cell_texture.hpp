// Texture in a sweep's window cells: cells that differ by the material's pattern, not by their
// directions (docs/method.md §9.4, "Textured materials").
#pragma once

#include <cstddef>
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
  /// \brief The most frames any one channel was measured in (under the rule's minFrames in
  /// every channel: no factors).
  int framesInBestChannel = 0;
  /// \brief Each cell position's albedo factor, row by row, per channel: the median over the
  /// frames of the cell's value over its frame's mean of cells (1 in a channel with too few
  /// frames measured). Empty when too few frames.
  std::vector<Rgb> albedoFactors;
  /// \brief How far the factors differ between positions: the root mean square of their
  /// logarithms about each channel's mean over the positions, less the scatter their medians have
  /// from the frames' own (CellTextureRule::spreadBeyondScatter), x 100 (about the spread in
  /// percent).
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
  /// \brief Texture when spreadPercent exceeds this: plain materials' sweeps measure 0-9.4 % (but
  /// 10-24 % on a few mirror sweeps), the woven 23-68 % (docs/results/2026-12-06-window-cells.md).
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
  /// \brief The spread counts what the factors hold beyond a level common to every position and
  /// beyond the scatter their medians have from the frames' own scatter (a lobe that the hand's
  /// jitter moves across the window changes each position's ratio from frame to frame; a pattern
  /// stays put). False: the root mean square of the log factors as they are (before 2026-12-07),
  /// which read 9 of 176 sweeps of plain materials on the virtual rig as textured, against 4.
  bool spreadBeyondScatter = true;
};

/// \brief Why `texture` (cellTextureOf with `rule`) got its action, in words for a person: the
/// figures the rule compared with its thresholds, e.g. "texture (spread 64 % over the 10 % of a
/// plain material) that the albedo factors do not explain: 10 % left, under 5 % needed" (the
/// status's "cell_texture.reason").
std::string verdictReason(const CellTexture& texture, const CellTextureRule& rule = {});

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

/// \brief A sweep still under way judged as its frames come (docs/method.md §9.5): the live
/// bins to pass again read its cells as this verdict says, so a textured window's thread is not
/// named a missed peak while the sweep runs. cellTextureOf reads every cell of the sweep (~10 ms
/// for 300 frames of 64 cells on a desktop core) and the status asks on every frame, so the
/// sweep is judged again only once its frames with cells have grown by `regrowth` since the
/// verdict kept (each frame while there are few): the cost over a sweep is a few full
/// judgements, and the verdict is never older than the last fifth or so of its frames.
class RunningCellTexture {
 public:
  explicit RunningCellTexture(CellTextureRule rule = {}, double regrowth = 1.25);
  /// \brief The verdict for `bins`, the running sweep's frames so far: judged again when their
  /// frames with cells reach `regrowth` x those of the kept verdict, or when they are another
  /// run's (AzimuthBins::run: the slice redone, or other bins), however many frames it has. With fewer than the rule's minFrames frames with cells no verdict can be
  /// made and the action is WindowCentres (the cells not read): the first frames of a textured
  /// sweep would otherwise name its thread a missed peak. Never throws.
  const CellTexture& of(const AzimuthBins& bins);
  /// \brief The frames with cells the kept verdict was judged on.
  std::size_t framesJudged() const { return framesJudged_; }

 private:
  CellTextureRule rule_;
  double regrowth_;
  std::size_t framesJudged_ = 0;
  std::optional<std::uint64_t> runJudged_;  // AzimuthBins::run() of the kept verdict
  CellTexture texture_;
};

}  // namespace slicecap::capture
