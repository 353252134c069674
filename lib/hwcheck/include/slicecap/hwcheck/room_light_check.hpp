// The room light from LED-off frames: its flicker (frequency, depth) from the rows of a rolling
// shutter, and its level against the LED's on the white references.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/linear_view.hpp"
#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/check_rig.hpp"
#include "slicecap/hwcheck/white_rows.hpp"

namespace slicecap::hwcheck {

/// \brief One LED-off frame's rows: the mean linear level of each (all columns, R+G+B) and when
/// row 0's exposure began.
struct RowProfile {
  std::vector<double> rowLevels;
  double row0StartUs = 0.0;
};

/// \brief The flicker fitted to rows of LED-off frames.
struct FlickerFit {
  std::optional<double> hz;  ///< none: no flicker above the noise, or none the frames can show
  double depth = 0.0;        ///< of the light itself: (max - min) / (max + min), IEEE 1789's / 100
  double explained = 0.0;    ///< the fit's share of the rows' variance about their means
  std::string problem;       ///< why there is no frequency (empty when there is one)
};

/// \brief Fits lamp flicker to LED-off frames' rows: each row r of frame f integrates the room
/// light over [row0StartUs + r * lineTimeUs, + exposureUs), and its level is the scene's (per
/// row, unknown) times 1 + depth' x cos(2 pi hz t + phase) at the window's middle. The scene is
/// taken out by each row's mean over the frames, which needs frames at different flicker phases
/// (a frame period that is not a whole number of flicker periods); the frequency is searched over
/// 40..250 Hz; depth' is divided by the exposure's attenuation sin(pi hz E) / (pi hz E) to give
/// the light's own depth. Pure: no camera.
FlickerFit fitFlicker(const std::vector<RowProfile>& frames, double lineTimeUs, double exposureUs);

/// \brief What the room-light check found.
struct RoomLightResult {
  FlickerFit flicker;
  double flickerExposureUs = 0.0;
  int flickerFrames = 0;
  /// The room light over the white references as a fraction of the LED's there, at the sweep's
  /// exposure (LED-off frames against LED-on ones); none when not measured.
  std::optional<double> roomToLed;
  /// The frame period the frames came at, to say whether it hides the flicker.
  double framePeriodUs = 0.0;
  std::string problem;
};

/// \brief With the scene still: LED-on and LED-off frames at `exposureUs` (the sweeps'
/// exposure) for the room-to-LED ratio over `whites`, then LED-off frames at a short exposure
/// (2 ms, gain raised to bring the room light up) for the flicker, each frame's rows decoded
/// through `codes` (16-bit frames as linear). `lineTimeUs`: the rows' spacing (measured by the
/// LED timing check, else the readout over the rows). Frames exposed across an LED switch are
/// skipped. Throws what CheckRig throws.
RoomLightResult measureRoomLight(CheckRig& rig, const WhiteRows& whites,
                                 const capture::CodeTable& codes, double exposureUs, double gain,
                                 double lineTimeUs, double framePeriodUs);

/// \brief The report's item: the flicker and the ratio, and what to set (mains_hz) or do (dim
/// the room) about them.
CheckItem roomLightItem(const RoomLightResult& result, const std::string& cameraId);

/// \brief The mains frequency whose lamps flicker at `flickerHz` (50 for 100 Hz, 60 for 120 Hz,
/// within 3 Hz), or none.
std::optional<int> mainsOfFlicker(double flickerHz);

}  // namespace slicecap::hwcheck
