// The mean of an area's light from 8-bit pixels that the camera's processing clipped at black.
#pragma once

#include <optional>

namespace slicecap::capture {

/// \brief What an area's 8-bit pixels of one channel say, decoded to linear light: their count,
/// how many are at code 0, the sum and the sum of squares of their decoded values, and `zeroTop`,
/// the linear value below which a pixel leaves the camera as code 0 (half-way to code 1).
struct ClippedPixels {
  int count = 0;
  int atZero = 0;
  double sum = 0.0, sumSquares = 0.0;
  double zeroTop = 0.0;
  /// The noise model's standard deviation at black (SensorNoise); 0: not known, not checked.
  double noiseSigma = 0.0;
};

/// \brief The mean light of pixels whose noise is one Gaussian clipped at black: the mean and
/// spread that give the fraction at code 0 and the mean of the decoded values (the censored
/// normal's two moments), when that spread is noise's (at most 4 x `noiseSigma`: an ISP's colour
/// gains and processing raise the sensor's) and the area's own spread agrees with the Gaussian's
/// within 35 %; nullopt when no pixel is at 0 (nothing to undo), all are, or the pixels are not
/// one clipped Gaussian (an area of dark and bright parts keeps its plain mean).
std::optional<double> unclippedMean(const ClippedPixels& pixels);

}  // namespace slicecap::capture
