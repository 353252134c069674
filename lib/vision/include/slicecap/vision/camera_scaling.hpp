// Whether a calibrated camera model scales to the size a camera delivers, asked before scaling.
#pragma once

#include <optional>
#include <string>

#include "slicecap/vision/camera_model.hpp"

namespace slicecap::vision {

/// \brief Why `camera` does not scale to `widthPx` x `heightPx` (a size that is not positive, or
/// another aspect ratio: another crop of the sensor), naming both sizes; nullopt when
/// CameraModel::scaledTo can. scaledTo throws this text as VisionError; a caller that has a way
/// on without the scaled model (the hardware check's failed item, the configured camera left
/// as calibrated) asks here instead of catching.
std::optional<std::string> scalingProblem(const CameraModel& camera, int widthPx, int heightPx);

}  // namespace slicecap::vision
