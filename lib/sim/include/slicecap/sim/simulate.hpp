// Simulated captures: one sweep as a recording with its truth, or a whole eight-slice session.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "slicecap/io/recording.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig.hpp"
#include "slicecap/sim/truth.hpp"

namespace slicecap::sim {

/// \brief What a simulated sweep renders: the rig, the material (its specification, for the
/// truth file), the camera and the target.
struct SweepSetup {
  RigParams rig;
  RenderSettings render;
  std::string materialSpec;
  vision::CameraModel camera = vision::defaultSimulatedCamera();
  vision::TargetGeometry target = vision::defaultTarget();
  std::string createdBy = "slicecap simulate";
};

/// \brief The exposure that puts the sweep's brightest window centre or white patch at 80 % of
/// full scale (a person setting the exposure for the sweep), in microseconds, 20 us .. 0.5 s.
double chooseExposureUs(const FrameRenderer& renderer, const RigParams& rig,
                        const std::vector<FramePlan>& plans);

/// \brief Renders one sweep into `directory` (which must not hold a recording yet): the
/// recording (recording.json + PNG frames) and truth.json. `progress` (if set) is called after
/// each frame with (done, total). Returns the truth. Throws io::IoError naming a path, or
/// std::invalid_argument for bad rig parameters.
SweepTruth simulateSweep(const std::filesystem::path& directory, const io::RecordedSlice& slice,
                         const FrameRenderer& renderer, const SweepSetup& setup,
                         const std::function<void(int, int)>& progress = {});

/// \brief The eight slices (axial and diagonal at 30/30, 30/75, 75/30, 75/75) as eight
/// recordings under `directory`, each with its truth. Returns their directories.
std::vector<std::filesystem::path> simulateSession(
    const std::filesystem::path& directory, const FrameRenderer& renderer, const SweepSetup& setup,
    const std::function<void(const std::string&)>& log = {});

}  // namespace slicecap::sim
