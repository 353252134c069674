// A sweep's rectified frames binned by slice parameter, kept per bin (never per frame): the
// bounded buffer of the active sweep and the combined texture of a finished one.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::btf {

/// \brief One accepted frame's texture: its rectified texels (R G B per texel, NaN where the
/// frame did not see the texel) and where the camera and the LED were (target frame, mm).
struct TextureFrame {
  double sliceParameterDeg = 0.0;  ///< of the window-centre sample: selects the bin
  Eigen::Vector3d cameraMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d lightMm = Eigen::Vector3d::Zero();
  std::vector<float> texels;
};

/// \brief One bin of a finished sweep: per texel and channel the median of its frames' values
/// (NaN where none saw the texel), at the mean camera and LED positions of those frames; a
/// texel's own light and view directions follow from its point and these positions.
struct TextureBin {
  int frames = 0;  ///< 0: an empty bin (no texels stored)
  Eigen::Vector3d cameraMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d lightMm = Eigen::Vector3d::Zero();
  std::vector<float> texels;
};

/// \brief A finished sweep as texture: one TextureBin per azimuth bin.
struct SliceTexture {
  SliceId slice;
  std::vector<TextureBin> bins;
  /// \brief Bytes of texel data held.
  std::size_t memoryBytes() const;
};

/// \brief Where a bin that keeps at most `framesPerBin` frames, those whose slice parameter is
/// nearest its centre `binCentreDeg`, puts a frame at `parameterDeg`, given its kept frames'
/// parameters: kept.size() (appended), the index of the kept frame it replaces (the farthest from
/// the centre), or nothing (not kept). Shared by the in-memory bins and the on-disk TextureStore.
std::optional<std::size_t> keepSlot(std::span<const double> keptParametersDeg, double parameterDeg,
                                    double binCentreDeg, int framesPerBin);

/// \brief A bin's frames combined: per texel and channel the median of the finite values (NaN
/// where no frame saw the texel), at the frames' mean camera and LED positions. Every frame must
/// hold texelCount x 3 values (BtfError otherwise); no frames give an empty bin.
TextureBin combineBinFrames(std::span<const TextureFrame> frames, std::size_t texelCount);

/// \brief The active sweep's bins. Each bin keeps at most `framesPerBin` frames, those whose
/// slice parameter is nearest the bin's centre (where the ideal slice sample sits): memory is
/// bounded by bins x framesPerBin x texels x 3 floats however long the sweep.
class SliceTextureBins {
 public:
  /// \brief Throws BtfError for framesPerBin < 1, no texels, or a bin width that
  /// does not divide 360.
  SliceTextureBins(SliceId slice, std::size_t texelCount, int framesPerBin = 5,
                   double binWidthDeg = 15.0);

  /// \brief Adds a frame (texels must hold texelCount x 3 values; BtfError
  /// otherwise). A full bin keeps the frames nearest its centre.
  void add(TextureFrame frame);
  /// \brief Per bin the per-texel median of its frames (robust to a frame the gate let through
  /// with a blurred or occluded part of the window).
  SliceTexture combine() const;

  const SliceId& slice() const { return slice_; }
  int binCount() const { return bins_.binCount(); }
  int filledCount() const;
  /// \brief Bytes of texel data held now (at most bins x framesPerBin x texels x 12).
  std::size_t memoryBytes() const;

 private:
  SliceId slice_;
  std::size_t texelCount_;
  int framesPerBin_;
  double binWidthDeg_;
  capture::AzimuthBins bins_;  // assignment only
  std::vector<std::vector<TextureFrame>> frames_;
};

}  // namespace slicecap::btf
