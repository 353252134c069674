// CameraModel::scaledTo: a calibration carried to a binned image of the same field of view.
#include <gtest/gtest.h>

#include <stdexcept>

#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/camera_scaling.hpp"
#include "slicecap/vision/vision_error.hpp"

namespace slicecap::vision {
namespace {

TEST(CameraModelScaledTo, APointProjectsWhereTheBinnedImageSeesIt) {
  // The camera module 3's processed 1280 x 720 and its RAW mode 2304 x 1296 binned to 1152 x 648
  // cover the same field of view: a point's pixel scales by 0.9 about the image's edge.
  const CameraModel camera = defaultSimulatedCamera();
  const CameraModel binned = camera.scaledTo(1152, 648);
  EXPECT_EQ(binned.intrinsics.widthPx, 1152);
  EXPECT_EQ(binned.intrinsics.heightPx, 648);
  EXPECT_EQ(binned.distortion, camera.distortion);
  for (const Eigen::Vector3d& point : {Eigen::Vector3d(0, 0, 300), Eigen::Vector3d(120, -70, 300),
                                      Eigen::Vector3d(-150, 80, 250)}) {
    const Eigen::Vector2d full = *camera.project(point);
    const Eigen::Vector2d small = *binned.project(point);
    // Pixel centres at integer coordinates: edges at -0.5 scale onto edges.
    EXPECT_NEAR(small.x(), (full.x() + 0.5) * 0.9 - 0.5, 1e-9);
    EXPECT_NEAR(small.y(), (full.y() + 0.5) * 0.9 - 0.5, 1e-9);
  }
  EXPECT_EQ(camera.scaledTo(1280, 720), camera);
}

TEST(CameraModelScaledTo, AnotherAspectRatioIsRefusedNamingBothSizes) {
  const CameraModel camera = defaultSimulatedCamera();
  try {
    (void)camera.scaledTo(1456, 1088);  // an IMX296's 4:3-ish mode: another crop
    FAIL() << "no error";
  } catch (const vision::VisionError& error) {
    EXPECT_NE(std::string(error.what()).find("1280x720"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("1456x1088"), std::string::npos) << error.what();
  }
  EXPECT_THROW((void)camera.scaledTo(0, 648), vision::VisionError);
}

// A caller with a way on asks first (no exception as a jump): the same text scaledTo throws.
TEST(CameraModelScaledTo, ScalingProblemIsWhatScaledToWouldThrow) {
  const CameraModel camera = defaultSimulatedCamera();
  EXPECT_EQ(scalingProblem(camera, 1152, 648), std::nullopt);
  const std::optional<std::string> problem = scalingProblem(camera, 1456, 1088);
  ASSERT_TRUE(problem.has_value());
  try {
    (void)camera.scaledTo(1456, 1088);
    FAIL() << "no error";
  } catch (const vision::VisionError& error) {
    EXPECT_EQ(*problem, error.what());
  }
  EXPECT_TRUE(scalingProblem(camera, 0, 648).has_value());
}

}  // namespace
}  // namespace slicecap::vision
