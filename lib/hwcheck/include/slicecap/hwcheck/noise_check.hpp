// The sensor's noise as the frames deliver it: read and shot noise, for the white-reference test.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/area_reading.hpp"
#include "slicecap/capture/response_curve.hpp"
#include "slicecap/hwcheck/check_report.hpp"
#include "slicecap/hwcheck/check_rig.hpp"
#include "slicecap/hwcheck/white_rows.hpp"

namespace slicecap::hwcheck {

/// \brief One exposure's pair of frames over the white references (one channel, linear).
struct NoisePoint {
  double exposureUs = 0.0;
  double gain = 1.0;
  double level = 0.0;     ///< mean linear level, fraction of full scale
  double variance = 0.0;  ///< per pixel, of one frame (half the pair difference's), quantisation out
  int pixels = 0;
};

struct NoiseResult {
  std::vector<NoisePoint> points;
  std::optional<capture::SensorNoise> noise;  ///< the fit, at unit gain
  int channel = 1;                            ///< 0 R, 1 G, 2 B: the channel fitted
  std::string problem;                        ///< why there is no fit
};

/// \brief Takes two frames at each of `exposuresUs` (LED on, the scene still) and reads, over the
/// white references, each pixel's channels decoded through `codes` (16-bit frames as linear): the pair's difference removes the print's and the lens's fixed pattern, half its
/// variance is one frame's noise, less the 8-bit step's quantisation (step^2 / 12). Fits
/// variance = readNoise^2 + level x gain / fullWellElectrons (capture::SensorNoise, the model
/// the white-reference test reads noise with) by least squares per channel, and returns the
/// noisiest channel's fit (at a tenth of full scale; the test uses one model for all channels,
/// and an underestimate would reject dark frames as occluded). What it measures is the noise
/// of the frames as delivered: an ISP's denoise lowers it, which is what the capture then sees.
/// Throws what CheckRig throws (a refused lock, no frames); a fit that is not possible is a
/// `problem`, not an exception.
NoiseResult measureSensorNoise(CheckRig& rig, const WhiteRows& whites, const capture::CodeTable& codes,
                               const std::vector<double>& exposuresUs);

/// \brief The pure part: the fit of `points` (at least 2 levels a factor 2 apart), or a problem.
NoiseResult fitSensorNoise(std::vector<NoisePoint> points);

CheckItem sensorNoiseItem(const NoiseResult& result, const std::string& cameraId);

}  // namespace slicecap::hwcheck
