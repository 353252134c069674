// The printed target as a camera sees it: the PNG, warped by a known homography, is detected by the
// AprilTag library with every marker id and corner where the target's geometry says.
#include "slicecap/vision/target.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "../support/apriltag_detector.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/target_print.hpp"

namespace slicecap::vision {
namespace {

// Warps `source` (1 channel) by `h` (source pixel -> destination pixel, OpenCV convention) with
// bilinear sampling; outside the source is mid-grey (a desk).
Image warp(const Image& source, const Eigen::Matrix3d& h, int width, int height) {
  const Eigen::Matrix3d inverse = h.inverse();
  Image out{width, height, 1, 8, std::vector<std::uint16_t>(std::size_t(width) * height, 90)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3d s = inverse * Eigen::Vector3d(x, y, 1.0);
      const double u = s.x() / s.z(), v = s.y() / s.z();
      const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
      if (u0 < 0 || v0 < 0 || u0 + 1 >= source.width || v0 + 1 >= source.height) continue;
      const double fu = u - u0, fv = v - v0;
      const double value = (1 - fu) * (1 - fv) * source.at(u0, v0, 0) + fu * (1 - fv) * source.at(u0 + 1, v0, 0) +
                           (1 - fu) * fv * source.at(u0, v0 + 1, 0) + fu * fv * source.at(u0 + 1, v0 + 1, 0);
      out.at(x, y, 0) = static_cast<std::uint16_t>(std::lround(value));
    }
  }
  return out;
}

Eigen::Vector2d apply(const Eigen::Matrix3d& h, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = h * Eigen::Vector3d(p.x(), p.y(), 1.0);
  return {q.x() / q.z(), q.y() / q.z()};
}

struct Case {
  const char* name;
  Eigen::Matrix3d homography;
};

TEST(TargetDetection, WarpedPngIsDetectedWithEveryIdAndCornerWhereTheJsonSays) {
  const auto dir = test::freshTempDir();
  const TargetGeometry target = defaultTarget();
  const double dpi = 150.0, pixelsPerMm = dpi / 25.4;
  io::writeTargetPng(dir / "target.png", target, dpi);
  const Image png = io::readPng(dir / "target.png");

  Eigen::Matrix3d tilted, rotated;
  // A perspective view (about 35 deg of tilt) and an in-plane rotation with shrink.
  tilted << 0.9, 0.25, 120.0, -0.05, 0.7, 90.0, 0.00005, 0.0006, 1.0;
  const double a = 0.6;
  rotated << 0.8 * std::cos(a), -0.8 * std::sin(a), 420.0, 0.8 * std::sin(a), 0.8 * std::cos(a), 20.0, 0, 0, 1;
  for (const Case& c : {Case{"tilted", tilted}, Case{"rotated", rotated}}) {
    const Image frame = warp(png, c.homography, 1100, 900);
    const auto found = test::detectTags(frame);
    ASSERT_EQ(found.size(), target.markers.size()) << c.name;
    double worst = 0.0;
    for (const Marker& m : target.markers) {
      ASSERT_TRUE(found.count(m.id)) << c.name << ": id " << m.id;
      for (int k = 0; k < 4; ++k) {
        // mm -> PNG pixel (pixel centres at integers) -> warped frame.
        const Eigen::Vector2d inPng((m.cornersMm[k].xMm - target.sheet.xMinMm) * pixelsPerMm - 0.5,
                                    (target.sheet.yMaxMm - m.cornersMm[k].yMm) * pixelsPerMm - 0.5);
        const Eigen::Vector2d expected = apply(c.homography, inPng);
        const auto& got = found.at(m.id).cornersPx[k];
        const double error = std::hypot(got[0] - expected.x(), got[1] - expected.y());
        worst = std::max(worst, error);
        EXPECT_LT(error, 0.3) << c.name << ": id " << m.id << " corner " << k;
      }
    }
    std::cout << c.name << ": worst corner error " << worst << " px\n";
  }
}

}  // namespace
}  // namespace slicecap::vision
