// tag36h11 marker detection with the AprilTag library, corners in OpenCV's pixel convention.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "slicecap/hal/frame.hpp"

namespace slicecap::capture {

/// \brief One detected tag: its id and corners p[0..3] (the library's order), pixels, pixel
/// centres at integer coordinates.
struct DetectedMarker {
  int id = 0;
  std::array<Eigen::Vector2d, 4> cornersPx{};
};

/// \brief A rectangle of the image, pixels (x0, y0 inclusive, width x height).
struct PixelRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};

/// \brief How finely one detect() call looks.
struct DetectionScale {
  /// \brief The library's quad_decimate: quads found on a 1/d image, the corners refined and the
  /// tags decoded on the image it is given.
  float quadDecimate = 1.0f;
  /// \brief The image given to the library averages binX x binY pixels: cheaper in proportion,
  /// and unlike quadDecimate it can be coarser along one axis than the other (a target seen at a
  /// grazing angle is foreshortened along one); the corners are refined at that resolution.
  int binX = 1, binY = 1;
};

/// \brief The range MarkerDetectorSettings::decimation must lie in. The library reads out of bounds
/// when the decimated image is under 3 pixels across (`--decimation 360` crashed `slicecap process`
/// on 720-row frames), and far below 16 every tag of a real frame is already lost.
inline constexpr float kMinDecimation = 1.0f;
inline constexpr float kMaxDecimation = 16.0f;

/// \brief Detector options.
struct MarkerDetectorSettings {
  /// \brief The library's quad_decimate for detect() without a scale (calibration views), and
  /// the second scale of MarkerSearch's whole-frame re-acquisition passes. 2 finds the quads on a
  /// half-size image and refines the corners on the full one (refine_edges): measured by
  /// bench/capture_bench.cpp (docs/results/2026-11-24-capture-accuracy.md) to be several
  /// times faster than 1 at 1280 x 720 with the same markers found at the rig's ~30 cm; 1 is for
  /// small or far targets. Must lie in kMinDecimation..kMaxDecimation.
  float decimation = 2.0f;
  /// \brief detect() without a scale: with fewer markers than this found after decimation,
  /// detect again at full resolution: at the 75 deg view elevation the tags are foreshortened to
  /// a quarter of their height and the half-size image loses most of them (measured on a
  /// simulated session: 9 of 24 LED-on frames of axial 75/75 kept at decimation 2 alone, 23 of 24
  /// with this). MarkerSearch has its own passes and does not use it.
  int fullResolutionBelow = 8;
  /// \brief When the pipeline tracks the target (it knows the latest pose), it predicts how each
  /// tag cell will appear and takes the coarsest of the library's decimations 3, 2, 1.5 that leaves
  /// every cell at least this many pixels across, in any direction, where the quads are found
  /// (the corners are still refined at full resolution). Measured on bench/capture_bench's sweeps
  /// and tests/capture/marker_detector_test.cpp: decimation 4 on cells of ~4.5 px (30 deg) missed
  /// a tag and put a corner 3.8 px off, so it is never offered; 1.4 gives 3 or 2 at 30 deg.
  double minDecimatedCellPx = 1.4;
  /// \brief Only when no decimation suits (the foreshortened views, where the cells are ~1.1-1.4
  /// px across one way and ~4.5 px the other): the coarsest binning along one axis (4, 3, 2) that
  /// leaves every cell this many binned pixels. 1.0 keeps every tag of a 75 deg sweep; 1.2 already
  /// rules binning out for most of its frames. Else full resolution.
  double minBinnedCellPx = 1.0;
  /// \brief The most detector work one frame may cost, in detectionWorkPx units (about the pixels
  /// the library searches at full resolution). A search that needs more goes on in the next
  /// frames (MarkerSearch) and the frame is rejected as "detection_deferred": the frame loop must
  /// not fall behind the camera. The default keeps every frame of bench/capture_bench's sweeps
  /// near the plain library's cost at decimation 2 or below (docs/detection.md); infinity
  /// searches every pass in the frame it is needed (the old behaviour, slow on a miss).
  double frameBudgetPx = 120000.0;
  /// \brief LED-on frames without a pose after which tracking gives up the last pose and the
  /// whole-frame re-acquisition passes start (one blurred frame or the arm's shadow should not
  /// cost a re-acquisition).
  int trackingPatienceFrames = 3;
};

/// \brief The detector work of searching a width x height area at `scale`, the unit of
/// MarkerDetectorSettings::frameBudgetPx: the pixels the library searches (after binning and
/// decimation), weighted by what one cost on bench/capture_bench's frames relative to a
/// full-resolution pixel (1.4 for decimation 2 and 3, which subsample and keep the noise that
/// makes many small quad candidates; 0.65 for decimation 1.5 and binning, which average it away),
/// plus the gray conversion of every pixel of the area (1/64).
double detectionWorkPx(int width, int height, const DetectionScale& scale);

/// \brief Wraps an apriltag_detector_t for tag36h11 (single-threaded, no blur: quad_sigma would
/// blur the buffer it is given). Not thread-safe; one per frame loop.
class MarkerDetector {
 public:
  /// \brief Throws CaptureError naming the value when settings.decimation is outside
  /// kMinDecimation..kMaxDecimation (or not a number).
  explicit MarkerDetector(MarkerDetectorSettings settings = {});
  ~MarkerDetector();
  MarkerDetector(const MarkerDetector&) = delete;
  MarkerDetector& operator=(const MarkerDetector&) = delete;

  /// \brief The markers in `frame` with no bit errors (an 8-bit gray view of the image: the mean
  /// of R, G, B; 16-bit linear samples are put on an sRGB-like curve first so the markers keep
  /// their contrast in the shadows).
  /// With `region`, only that part of the image (clamped to it) is searched: the target's area
  /// from the previous pose, the detector's cost being proportional to the pixels it sees.
  /// With `scale`, that scale and no full-resolution retry (the caller predicted the resolution
  /// the markers need); without, settings' decimation and retry. A pass whose image would be
  /// too small for the library (a few pixels across after decimation) finds nothing.
  std::vector<DetectedMarker> detect(const hal::Frame& frame,
                                     const std::optional<PixelRect>& region = std::nullopt,
                                     const std::optional<DetectionScale>& scale = std::nullopt);
  /// \brief Detections of the last detect() that needed the full-resolution retry.
  bool lastNeededFullResolution() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// \brief apriltag 3.3 places pixel centres at +0.5 (measured in
/// tests/vision/target_test.cpp); subtracting it gives OpenCV's convention.
inline constexpr double kApriltagPixelOffset = 0.5;

}  // namespace slicecap::capture
