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

/// \brief Detector options.
struct MarkerDetectorSettings {
  /// \brief The library's quad_decimate. 2 finds the quads on a half-size image and refines the
  /// corners on the full one (refine_edges): measured by bench/capture_bench.cpp (see the README
  /// section "Processing recordings") to be several times faster than 1 at 1280 x 720 with the
  /// same markers found at the rig's ~30 cm; 1 is for small or far targets.
  float decimation = 2.0f;
  /// \brief With fewer markers than this found after decimation, detect again at full
  /// resolution: at the 75 deg view elevation the tags are foreshortened to a quarter of their
  /// height and the half-size image loses most of them (measured on a simulated session: 9 of 24
  /// LED-on frames of axial 75/75 kept at decimation 2 alone, 23 of 24 with this).
  int fullResolutionBelow = 8;
  /// \brief When the pipeline tracks the target (it knows the previous frame's pose), it
  /// predicts the smallest image size of a tag cell and asks for the coarsest decimation (4, 3,
  /// 2, 1.5 or 1) that leaves each cell at least this many pixels of the decimated image, with no
  /// retry: the corners are still refined on the full-resolution image.
  double minDecimatedCellPx = 1.0;
};

/// \brief Wraps an apriltag_detector_t for tag36h11 (single-threaded, no blur: quad_sigma would
/// blur the buffer it is given). Not thread-safe; one per frame loop.
class MarkerDetector {
 public:
  explicit MarkerDetector(MarkerDetectorSettings settings = {});
  ~MarkerDetector();
  MarkerDetector(const MarkerDetector&) = delete;
  MarkerDetector& operator=(const MarkerDetector&) = delete;

  /// \brief The markers in `frame` with no bit errors (an 8-bit gray view of the image: the mean
  /// of R, G, B; 16-bit linear samples are put on an sRGB-like curve first so the markers keep
  /// their contrast in the shadows).
  /// With `region`, only that part of the image (clamped to it) is searched: the target's area
  /// from the previous pose, the detector's cost being proportional to the pixels it sees.
  /// With `decimation`, the library's quad_decimate for this call and no full-resolution retry
  /// (the caller predicted the resolution the markers need); without, settings' decimation and
  /// retry.
  std::vector<DetectedMarker> detect(const hal::Frame& frame,
                                     const std::optional<PixelRect>& region = std::nullopt,
                                     std::optional<float> decimation = std::nullopt);
  /// \brief Detections of the last detect() that needed the full-resolution retry.
  bool lastNeededFullResolution() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// \brief apriltag 3.3 places pixel centres at +0.5 (measured in
/// tests/vision/target_detection_test.cpp); subtracting it gives OpenCV's convention.
inline constexpr double kApriltagPixelOffset = 0.5;

}  // namespace slicecap::capture
