// tag36h11 detection: an 8-bit gray copy of the frame handed to the AprilTag library.
#include "slicecap/capture/marker_detector.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "slicecap/capture/capture_error.hpp"

namespace slicecap::capture {

struct MarkerDetector::State {
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
  image_u8_t* gray = nullptr;
  std::vector<std::uint8_t> linearToGray;  // 16-bit linear -> 8-bit, square-root curve
  MarkerDetectorSettings settings;
  bool retried = false;
};

namespace {

std::vector<DetectedMarker> runDetector(apriltag_detector_t* detector, image_u8_t* gray,
                                        const PixelRect& area, int binX, int binY) {
  zarray_t* detections = apriltag_detector_detect(detector, gray);
  std::vector<DetectedMarker> found;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(detections, i, &d);
    if (d->hamming > 0) continue;
    DetectedMarker marker{d->id, {}};
    // A binned pixel i covers full pixels i*b .. i*b + b - 1: its centre is at i*b + (b - 1)/2.
    for (int c = 0; c < 4; ++c)
      marker.cornersPx[c] = {
          (d->p[c][0] - kApriltagPixelOffset) * binX + (binX - 1) / 2.0 + area.x0,
          (d->p[c][1] - kApriltagPixelOffset) * binY + (binY - 1) / 2.0 + area.y0};
    found.push_back(marker);
  }
  apriltag_detections_destroy(detections);
  return found;
}

// The library finds quads on the image decimated as apriltag 3.3 does it (1.5: two thirds of each
// side; else every d-th pixel) and reads out of bounds when that image is under 3 pixels across.
// No tag fits in so few pixels, so such a pass is skipped (one pixel of margin).
bool librarySearchable(int width, int height, float quadDecimate) {
  const auto decimatedSide = [quadDecimate](int side) {
    if (quadDecimate <= 1.0f) return side;
    if (quadDecimate == 1.5f) return side / 3 * 2;
    return 1 + (side - 1) / static_cast<int>(quadDecimate);
  };
  constexpr int kSmallestSearchablePx = 4;
  return decimatedSide(width) >= kSmallestSearchablePx &&
         decimatedSide(height) >= kSmallestSearchablePx;
}

}  // namespace

MarkerDetector::MarkerDetector(MarkerDetectorSettings settings)
    : state_(std::make_unique<State>()) {
  if (!(settings.decimation >= kMinDecimation && settings.decimation <= kMaxDecimation)) {
    std::ostringstream message;
    message << "marker detector: decimation " << settings.decimation << " is outside "
            << kMinDecimation << ".." << kMaxDecimation;
    throw CaptureError(message.str());
  }
  if (!(settings.frameBudgetPx > 0.0)) {
    std::ostringstream message;
    message << "marker detector: frame budget " << settings.frameBudgetPx
            << " px is not positive";
    throw CaptureError(message.str());
  }
  state_->settings = settings;
  state_->family = tag36h11_create();
  state_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(state_->detector, state_->family, 1);
  state_->detector->quad_decimate = settings.decimation;
  state_->detector->quad_sigma = 0.0f;
  state_->detector->nthreads = 1;
  state_->detector->refine_edges = true;
  state_->linearToGray.resize(65536);
  for (int i = 0; i < 65536; ++i)
    state_->linearToGray[i] =
        static_cast<std::uint8_t>(std::lround(255.0 * std::sqrt(i / 65535.0)));
}

MarkerDetector::~MarkerDetector() {
  if (state_->gray) image_u8_destroy(state_->gray);
  apriltag_detector_destroy(state_->detector);
  tag36h11_destroy(state_->family);
}

std::vector<DetectedMarker> MarkerDetector::detect(const hal::Frame& frame,
                                                   const std::optional<PixelRect>& region,
                                                   const std::optional<DetectionScale>& scale) {
  const Image& image = frame.image;
  PixelRect area{0, 0, image.width, image.height};
  if (region) {
    const int x0 = std::clamp(region->x0, 0, image.width),
              y0 = std::clamp(region->y0, 0, image.height);
    const int x1 = std::clamp(region->x0 + region->width, 0, image.width);
    const int y1 = std::clamp(region->y0 + region->height, 0, image.height);
    if (x1 - x0 >= 16 && y1 - y0 >= 16) area = {x0, y0, x1 - x0, y1 - y0};
  }
  int binX = scale ? std::max(1, scale->binX) : 1, binY = scale ? std::max(1, scale->binY) : 1;
  if (area.width / binX < 16 || area.height / binY < 16) binX = binY = 1;
  const int grayWidth = area.width / binX, grayHeight = area.height / binY;
  if (!state_->gray || state_->gray->width != grayWidth || state_->gray->height != grayHeight) {
    if (state_->gray) image_u8_destroy(state_->gray);
    state_->gray = image_u8_create(grayWidth, grayHeight);
  }
  image_u8_t* gray = state_->gray;
  const int used = image.channels >= 3 ? 3 : 1;
  const bool linear = image.bitDepth == 16;
  // A RAW frame's black sits above 0 (Frame::black16): taken off, and the span above it
  // stretched back to 0..65535, so black is black to the detector.
  const int black = linear ? frame.black16 : 0;
  const auto aboveBlack = [black](int mean) {
    return black == 0 ? mean
                      : int(std::int64_t{std::max(0, mean - black)} * 65535 / (65535 - black));
  };
  const std::uint16_t* in = image.samples.data();
  // Each pixel is put on the 8-bit curve before a bin is averaged, so a binned edge lies where
  // the full-resolution one does (averaging linear light first would move it toward the dark side).
  const auto grayOf = [&](const std::uint16_t* px) {
    int sum = 0;
    for (int c = 0; c < used; ++c)
      sum += px[c];
    const int mean = sum / used;
    return linear ? int{state_->linearToGray[std::size_t(aboveBlack(mean))]} : mean;
  };
  const int binPixels = binX * binY;
  for (int y = 0; y < grayHeight; ++y) {
    std::uint8_t* row = gray->buf + static_cast<std::size_t>(y) * gray->stride;
    for (int x = 0; x < grayWidth; ++x) {
      int sum = 0;
      for (int by = 0; by < binY; ++by) {
        const std::uint16_t* px =
            in + (static_cast<std::size_t>(area.y0 + y * binY + by) * image.width + area.x0 +
                  static_cast<std::size_t>(x) * binX) *
                     image.channels;
        for (int bx = 0; bx < binX; ++bx, px += image.channels)
          sum += grayOf(px);
      }
      row[x] = static_cast<std::uint8_t>((sum + binPixels / 2) / binPixels);
    }
  }
  state_->detector->quad_decimate = scale ? scale->quadDecimate : state_->settings.decimation;
  std::vector<DetectedMarker> found;
  if (librarySearchable(grayWidth, grayHeight, state_->detector->quad_decimate))
    found = runDetector(state_->detector, gray, area, binX, binY);
  state_->retried = false;
  if (!scale && static_cast<int>(found.size()) < state_->settings.fullResolutionBelow &&
      state_->settings.decimation > 1.0f && librarySearchable(grayWidth, grayHeight, 1.0f)) {
    state_->detector->quad_decimate = 1.0f;
    std::vector<DetectedMarker> full = runDetector(state_->detector, gray, area, 1, 1);
    state_->retried = true;
    if (full.size() > found.size()) found = std::move(full);
  }
  return found;
}

double detectionWorkPx(int width, int height, const DetectionScale& scale) {
  const int binX = std::max(1, scale.binX), binY = std::max(1, scale.binY);
  const double d = std::max(1.0f, scale.quadDecimate);
  const double searched = static_cast<double>(width / binX) * (height / binY) / (d * d);
  const bool averaged = binX * binY > 1 || scale.quadDecimate == 1.5f;
  const double weight = averaged ? 0.65 : (d > 1.0 ? 1.4 : 1.0);
  return weight * searched + static_cast<double>(width) * height / 64.0;
}

bool MarkerDetector::lastNeededFullResolution() const {
  return state_->retried;
}

}  // namespace slicecap::capture
