// truth.json: what really happened in each simulated frame (pose, light, BRDF, expected pixel).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "slicecap/core/grid.hpp"
#include "slicecap/core/rgb.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/vision/pose.hpp"

namespace slicecap::sim {

/// \brief The truth of one frame. Directions are those of the window centre (target frame).
struct FrameTruth {
  std::string file;
  std::int64_t timestampUs = 0;
  bool ledOn = true;
  double exposureUs = 0.0;
  double gain = 1.0;
  double sliceParameterDeg = 0.0;  ///< nominal position on the slice
  vision::Pose pose;               ///< camera-from-target at mid-exposure
  Direction view;                  ///< toward the camera
  double cameraDistanceMm = 0.0;
  Eigen::Vector3d lightMm = Eigen::Vector3d::Zero();
  Direction light;             ///< toward the LED
  double ledIrradiance = 0.0;  ///< W/m^2 at the window centre (0 with the LED off)
  Rgb brdf;                    ///< the material's BRDF for `light` and `view`, 1/sr
  Rgb expectedLinear;          ///< noise-free linear pixel at the window centre (1 = full scale)
  double motionBlurPx = 0.0;   ///< how far the window centre moved in the image while exposed
  bool occluded = false;       ///< the light arm hides part of the image near the window
  bool aimedOff = false;       ///< aimed so that part of the target is out of the image
  std::vector<int> markersInView;  ///< ids whose four corners are in the image and not occluded
};

/// \brief The truth of one simulated recording.
struct SweepTruth {
  std::string material;             ///< the specification given to simulate
  std::string materialDescription;  ///< the model's describe()
  io::RecordedSlice slice;
  double ledIntensityWPerSr = 0.0;
  double sensorResponse = 0.0;
  double ambientIrradiance = 0.0;
  std::vector<FrameTruth> frames;
};

/// \brief The truth file's name inside a simulated recording.
inline constexpr const char* kTruthFile = "truth.json";

/// \brief Writes `directory`/truth.json (atomically). Throws io::IoError naming the path.
void writeTruth(const std::filesystem::path& directory, const SweepTruth& truth);
/// \brief Reads `directory`/truth.json. Throws io::IoError naming the path and field.
SweepTruth readTruth(const std::filesystem::path& directory);

}  // namespace slicecap::sim
