// The AprilTag library's tag36h11 detector as the tests use it: corners in OpenCV's pixel
// convention (pixel centres at integer coordinates).
#pragma once

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/common/zarray.h>
#include <apriltag/tag36h11.h>

#include <array>
#include <map>
#include <memory>

#include "slicecap/core/image.hpp"

namespace slicecap::test {

/// \brief One detected tag: id and its corners p[0..3] in pixels (OpenCV convention).
struct DetectedTag {
  int id = 0;
  std::array<std::array<double, 2>, 4> cornersPx{};
};

/// \brief apriltag 3.3 places pixel centres at +0.5 (measured in
/// tests/vision/target_test.cpp); subtracting it gives OpenCV's convention.
inline constexpr double kApriltagPixelOffset = 0.5;

/// \brief Detects tag36h11 markers (no decimation, no blur) in an 8-bit gray view of `image`
/// (its first channel, or the sRGB mean of RGB for 3 channels; 16-bit samples are scaled to 8).
inline std::map<int, DetectedTag> detectTags(const Image& image) {
  image_u8_t* gray = image_u8_create(image.width, image.height);
  const int shift = image.bitDepth == 16 ? 8 : 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      int sum = 0;
      const int used = image.channels >= 3 ? 3 : 1;
      for (int c = 0; c < used; ++c)
        sum += image.at(x, y, c) >> shift;
      gray->buf[y * gray->stride + x] = static_cast<uint8_t>(sum / used);
    }
  }
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(detector, family, 1);
  detector->quad_decimate = 1.0f;
  detector->quad_sigma = 0.0f;
  detector->nthreads = 1;
  detector->refine_edges = true;
  zarray_t* detections = apriltag_detector_detect(detector, gray);
  std::map<int, DetectedTag> found;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(detections, i, &d);
    if (d->hamming > 0) continue;
    DetectedTag tag{d->id, {}};
    for (int c = 0; c < 4; ++c)
      tag.cornersPx[c] = {d->p[c][0] - kApriltagPixelOffset, d->p[c][1] - kApriltagPixelOffset};
    found[d->id] = tag;
  }
  apriltag_detections_destroy(detections);
  apriltag_detector_destroy(detector);
  tag36h11_destroy(family);
  image_u8_destroy(gray);
  return found;
}

}  // namespace slicecap::test
