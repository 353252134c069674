// Slices (docs/method.md §2): the two kinds, the measured elevation pairs, samples at any azimuth.
#pragma once

#include <array>
#include <compare>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"

namespace slicecap {

/// \brief Axial: camera and light keep phi_v = phi_i + 15 deg. Diagonal: phi_i = 360 - phi_v.
/// Point: a sample at its own light and view directions, on no slice (e.g. the uniform 13 x 13
/// baseline of docs/method.md §6.3); such samples are grouped by their nominal elevation pair only.
enum class SliceKind { Axial, Diagonal, Point };

/// \brief The axial slice's azimuth offset alpha_A (the paper's alpha).
inline constexpr double kAxialOffsetDeg = 15.0;

/// \brief "axial", "diagonal" or "point" (the spelling of the slice CSV).
std::string_view toString(SliceKind kind);
/// \brief The kind spelled exactly "axial", "diagonal" or "point", or nullopt.
std::optional<SliceKind> parseSliceKind(std::string_view text);

/// \brief Nominal light and view elevations of a slice, whole degrees.
struct ElevationPair {
  int thetaIDeg = 0;
  int thetaVDeg = 0;
  friend constexpr auto operator<=>(const ElevationPair&, const ElevationPair&) = default;
};

/// \brief The four pairs the rig measures (docs/method.md §2.1), in this order.
inline constexpr std::array<ElevationPair, 4> kMeasuredPairs{
    {{30, 30}, {30, 75}, {75, 30}, {75, 75}}};
/// \brief The elevations the rig measures; Method B interpolates and extrapolates from them.
inline constexpr std::array<int, 2> kMeasuredElevationsDeg{30, 75};

/// \brief Which slice: kind and nominal elevation pair.
struct SliceId {
  SliceKind kind = SliceKind::Diagonal;
  ElevationPair elevations;
  friend constexpr auto operator<=>(const SliceId&, const SliceId&) = default;
};

/// \brief e.g. "axial 30/75".
std::string toString(const SliceId& id);
/// \brief e.g. "axial-30-75": how a slice's recording and texture folders are named.
std::string folderName(const SliceId& id);

/// \brief One measured (or simulated) BRDF sample at its actual light and view directions.
struct SliceSample {
  Direction light;
  Direction view;
  Rgb value;  ///< linear BRDF, 1/sr
};

/// \brief One window cell as a point of its own (docs/method.md §9.4, "The prior on every cell"):
/// its directions and value, and the variance of its value from the noise model.
struct CellPoint {
  SliceSample sample;
  Rgb variance;  ///< of sample.value; 0 for a reading whose noise is not known
};

/// \brief The usable cells of one frame. They share the frame's pose, exposure and irradiance
/// fit, so their errors are correlated: a method that fits them takes them as one group.
using FrameCellPoints = std::vector<CellPoint>;

/// \brief The light and view azimuths of a point on a slice's line.
struct AzimuthPair {
  double phiIDeg = 0.0;
  double phiVDeg = 0.0;
};

/// \brief The slice parameter of a sample: its light azimuth on an axial slice, its view azimuth on
/// a diagonal slice (docs/method.md §2.1), in [0, 360). Point samples have none (throws
/// CoreError).
double sliceParameterDeg(SliceKind kind, const SliceSample& sample);

/// \brief The point of the slice line at a parameter: axial (x, x + 15), diagonal (360 - x, x),
/// both wrapped to [0, 360). Point samples lie on no line (CoreError).
AzimuthPair slicePoint(SliceKind kind, double parameterDeg);

/// \brief One slice: its identity and its samples in capture order.
struct Slice {
  SliceId id;
  std::vector<SliceSample> samples;
  /// \brief A capture's other reading of the same slice: each bin's value taken from the window
  /// cells nearest the bin centre in angle (lib/capture window_cells.hpp, docs/method.md §9),
  /// which a method may read instead of `samples` (b-cells). Empty when the samples have no
  /// cells (a slice CSV, ideal slices of a table, a journal written before cells).
  std::vector<SliceSample> cellSamples{};
  /// \brief Every usable cell of the slice's frames, frame by frame (a bin no usable cell reached
  /// is a group of its window-centre sample, variance 0), for a method that fits each cell as a
  /// point (the prior's `PriorParams::fitEveryCell`). Empty where cellSamples is, and where the
  /// cells were not kept (a slice CSV; a textured window read as its centres).
  std::vector<FrameCellPoints> cellFrames{};
};

/// \brief The slices of one material (up to 8 in a full capture; any subset is representable).
/// Slices are kept ordered by SliceId; an empty slice is never stored.
class SliceSet {
 public:
  /// \brief Appends a sample to the slice `id`, creating the slice on first use.
  void add(const SliceId& id, const SliceSample& sample);
  /// \brief Appends a sample to the cell samples of the slice `id` (Slice::cellSamples). The
  /// slice must have samples already (CoreError naming it otherwise): a cell reading
  /// comes from frames, whose window centres are samples too.
  void addCellSample(const SliceId& id, const SliceSample& sample);
  /// \brief Appends one frame's cell points to the slice `id` (Slice::cellFrames); CoreError
  /// as addCellSample. An empty group is not stored.
  void addCellFrame(const SliceId& id, FrameCellPoints cells);
  /// \brief True when some slice has cell frames.
  bool hasCellFrames() const;
  /// \brief True when some slice has cell samples.
  bool hasCellSamples() const;
  /// \brief The set with each slice's cell samples as its samples where it has any (its own
  /// samples elsewhere), and no cell samples; each slice's cell frames are kept.
  SliceSet cellReading() const;
  /// \brief The slice with this id, or nullptr when it has no samples.
  const Slice* find(const SliceId& id) const;
  const std::vector<Slice>& slices() const { return slices_; }
  std::size_t sampleCount() const;
  bool empty() const { return slices_.empty(); }

 private:
  std::vector<Slice> slices_;
};

}  // namespace slicecap
