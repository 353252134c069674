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

/// \brief The brightest radiances (W / (m^2 sr), LED on, any channel) over a sweep's planned
/// positions: the window centre's, the window's sample square's (the part of the window the
/// capture reads, kMeteredSquareFraction of its side: off the mirror direction, a sharp lobe's
/// brightest point is off the centre), and the white references' (their centres, room light
/// included).
struct MeteredRadiance {
  double window = 0.0;
  double references = 0.0;
  double windowSquare = 0.0;
};
/// \brief The side of the square metered for HDR's short level, as a fraction of the window's:
/// capture::PipelineSettings::windowSampleFraction's default.
inline constexpr double kMeteredSquareFraction = 0.2;
MeteredRadiance meterSweep(const FrameRenderer& renderer, const RigParams& rig,
                           const std::vector<FramePlan>& plans);

/// \brief The one exposure of a sweep (a person setting it), in microseconds, 20 us .. 0.5 s:
/// the brightest window centre or white patch at 80 % of full scale (RigParams::Metering::
/// Brightest), or the brightest white patch alone (Paper).
double chooseExposureUs(const FrameRenderer& renderer, const RigParams& rig,
                        const std::vector<FramePlan>& plans);

/// \brief HDR levels differ at least this much (the window at least this much brighter than the
/// paper), else one exposure holds both.
inline constexpr double kHdrMinRatio = 2.0;
/// \brief Two levels at most this far apart; a wider range gets a third level between them (8-bit
/// frames keep ~6 bits of a value 16 times below the level that holds it).
inline constexpr double kHdrMaxStepRatio = 16.0;

/// \brief The HDR metering rule (docs/method.md, HDR capture), longest first, each 20 us .. 0.5 s:
/// level 0 puts the brightest white reference at 80 % of full scale (the paper: the irradiance
/// and the dark parts of the lobe), the last level the brightest point of the window's sample
/// square (the highlight: every cell of the square unclipped);
/// a third, their geometric mean, when rig.maxExposureLevels is 3 and they are more than
/// kHdrMaxStepRatio apart. One level (the Brightest rule) when rig.maxExposureLevels is 1 or the
/// window is less than kHdrMinRatio brighter than the paper.
std::vector<double> chooseHdrLevelsUs(const MeteredRadiance& metered, const RigParams& rig);

/// \brief Renders one sweep into `directory` (which must not hold a recording yet): the
/// recording (recording.json + PNG frames) and truth.json. `progress` (if set) is called after
/// each frame with (done, total). Returns the truth. Throws io::IoError naming a path, or
/// SimError for bad rig parameters.
SweepTruth simulateSweep(const std::filesystem::path& directory, const io::RecordedSlice& slice,
                         const FrameRenderer& renderer, const SweepSetup& setup,
                         const std::function<void(int, int)>& progress = {});

/// \brief The eight slices (axial and diagonal at 30/30, 30/75, 75/30, 75/75) as eight
/// recordings under `directory`, each with its truth. Returns their directories.
std::vector<std::filesystem::path> simulateSession(
    const std::filesystem::path& directory, const FrameRenderer& renderer, const SweepSetup& setup,
    const std::function<void(const std::string&)>& log = {});

}  // namespace slicecap::sim
