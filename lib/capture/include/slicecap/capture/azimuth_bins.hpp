// Binning a sweep's frames by the slice parameter (15 deg bins) and combining each bin robustly.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/capture/hdr_merge.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::capture {

/// \brief The bins of one slice: bin k is centred on parameter k * width (the positions of the
/// ideal slice samples) and spans half a width either side. The parameter is the light azimuth on
/// an axial slice and the view azimuth on a diagonal one (sliceParameterDeg).
class AzimuthBins {
 public:
  /// \brief `binWidthDeg` must divide 360 (CaptureError otherwise); 15 deg gives 24 bins.
  explicit AzimuthBins(SliceKind kind, double binWidthDeg = 15.0);

  int binCount() const { return static_cast<int>(bins_.size()); }
  SliceKind kind() const { return kind_; }
  double binWidthDeg() const { return binWidthDeg_; }
  /// \brief The bin a slice parameter falls in.
  int binOf(double parameterDeg) const;
  /// \brief The bin of a sample's slice parameter.
  int binOf(const FrameSample& sample) const;

  /// \brief Changes whenever the bins do (add, clear), unique across every AzimuthBins of the
  /// process: what is worked out from the bins can be kept while it stays the same.
  std::uint64_t version() const { return version_; }
  /// \brief Which run of samples the bins hold: set when they are made and on clear() (a redone
  /// sweep), kept by add() (a sweep continued joins its run), unique across every AzimuthBins of
  /// the process. What is judged of a run's samples (RunningCellTexture) is keyed on it.
  std::uint64_t run() const { return run_; }

  void add(const FrameSample& sample);
  /// \brief Removes every sample (a redone sweep).
  void clear();
  /// \brief Removes the sample last added to bin `bin` (newest first: a refused sweep run's
  /// samples are the latest of their bins). Nothing if the bin is empty.
  void removeLatest(int bin);

  const std::vector<FrameSample>& samplesIn(int bin) const { return bins_[bin]; }
  int filledCount() const;
  std::vector<bool> filled() const;

  /// \brief One slice sample per non-empty bin: the per-channel median of its values (robust to a
  /// blurred or occluded frame that passed the gate) or, when every sample of the bin carries an
  /// HDR reading, their merge (mergeHdrBin), at the mean light and view directions of its
  /// frames (elevations averaged, azimuths by circular mean): the sample sits at the measured
  /// angles, not at the bin centre.
  std::vector<SliceSample> combine() const;
  /// \brief combine()'s sample of bin `bin`; nullopt for an empty bin.
  std::optional<SliceSample> combineBin(int bin) const;
  /// \brief The bins of an HDR sweep whose merged value rests on a clipped window cell
  /// (HdrMerge::clippedCells, the merge combine() makes: a cell clipped in every frame, or whose
  /// frames disagree and the one nearest the bin centre clipped): the value may be far too low
  /// (on a sharp highlight, its clipped reading, a lower bound), and only frames taken at a
  /// shorter exposure there mend it. Ascending; empty for a sweep of one exposure, which rejects
  /// a clipped window.
  std::vector<int> clippedBins() const;

 private:
  /// The merge of bin b's HDR readings as combine() makes it (nullopt: not an HDR bin).
  std::optional<HdrMerge> mergedHdr(std::size_t b) const;

  SliceKind kind_;
  double binWidthDeg_;
  std::vector<std::vector<FrameSample>> bins_;
  std::uint64_t version_;
  std::uint64_t run_;
  mutable std::optional<std::vector<int>> clippedCache_;  // clippedBins() until add or clear
};

}  // namespace slicecap::capture
