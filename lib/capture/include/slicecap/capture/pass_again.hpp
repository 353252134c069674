// The bins of a sweep to pass over again, slowly: left empty, or next to a lobe whose peak no
// frame's window reached (docs/method.md §9.5).
#pragma once

#include <string>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/capture/window_cell_texture.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::capture {

/// \brief Why a bin is to be passed again.
enum class PassAgainReason {
  Empty,           ///< no frame's centre and no usable cell fell in it
  PeakNotReached,  ///< the cells rise steeply toward the bin centre, which none reached
};

/// \brief "empty" or "peak_not_reached" (the status's and the report's word).
std::string toString(PassAgainReason reason);

/// \brief One bin to pass again: its slice, its azimuth (the slice parameter of its centre:
/// light azimuth on an axial slice, view azimuth on a diagonal one) and why.
struct PassAgainBin {
  SliceId slice;
  int bin = 0;
  double azimuthDeg = 0.0;
  PassAgainReason reason = PassAgainReason::Empty;
};

/// \brief Whether the sweep is still under way: its empty bins ahead of it are not yet missed.
enum class SweepProgress { Running, Finished };

/// \brief When the cells say a peak was missed (binsToPassAgain). The defaults follow from the
/// geometry of the default target (docs/method.md §9.4): neighbouring cells lie 1.1-1.3 deg
/// apart in the slice-value rule's distance (sqrt(light angle^2 + view angle^2)), so a window
/// that covers a bin centre has a cell within ~0.9 deg of it (half a cell's diagonal); a sharp
/// metal's mirror peak is ~0.6-0.75 deg wide, about one cell.
struct PassAgainRule {
  /// \brief The bin centre counts as reached when a usable cell lies within this of it: over
  /// half a cell's diagonal, so only a gap in the windows' coverage (no window over the centre)
  /// exceeds it.
  double reachedWithinDeg = 1.0;
  /// \brief The cells at the edge of the coverage: within this of the nearest cell (the slice
  /// value's own pool, CellSliceRule::poolToleranceDeg).
  double edgeBandDeg = 0.5;
  /// \brief The cells the edge is compared with: from one to two and a half cell steps
  /// (1.2 deg each) farther from the bin centre than the nearest cell.
  double farFromDeg = 1.2;
  double farToDeg = 3.0;
  /// \brief "Rising steeply": the edge at least this many times the cells a step or two
  /// behind it. A lobe that doubles within ~2 deg is under ~5 deg wide (Ward alpha under ~0.1);
  /// its value at a centre still 1 deg or more beyond the edge is far above the edge's, and no
  /// broad lobe or diffuse slope changes this much over two cell steps.
  double riseFactor = 2.0;
  /// \brief And the rise above the cells' noise by this many standard deviations, so a dim,
  /// noisy bin is not named.
  double noiseSigmas = 3.0;
};

/// \brief The bins of a sweep of slice `id` (its frames in `bins`, with their window cells) to
/// pass again, ascending by bin. A bin is:
/// - Empty when no frame's centre and no unclipped cell (by its own slice parameter) fell in it,
///   the bins sliceFromCells leaves without a value. While the sweep runs (`progress` Running)
///   its longest run of empty bins is the part still ahead of it and is not named; the other
///   runs are gaps it left behind. A slice without samples names nothing (it is not swept).
/// - PeakNotReached when the bin's cells nearest its centre are more than
///   rule.reachedWithinDeg from it and rise steeply toward it (PassAgainRule): the cells of the
///   bin and its two neighbours within rule.edgeBandDeg of the nearest are at least
///   rule.riseFactor times, and rule.noiseSigmas standard deviations above, those
///   rule.farFromDeg-rule.farToDeg farther out. Only frames that carry cells can show this.
///   The cells are read as the sweep's `texture` verdict (cellTextureOf of these bins) says
///   (cellsAsJudged): as read, divided by the albedo factors, or, for WindowCentres, not at
///   all (a thread's colour is no missed peak; empty bins are still named). The default
///   verdict (none measured) reads them as they are. The caller judges the texture, once a
///   sweep: the verdict is not made here, where the status asks on every new frame.
/// Throws CaptureError for a point slice.
std::vector<PassAgainBin> binsToPassAgain(const AzimuthBins& bins, const SliceId& id,
                                          SweepProgress progress, const PassAgainRule& rule = {},
                                          const CellTexture& texture = {});

}  // namespace slicecap::capture
