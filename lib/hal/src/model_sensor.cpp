// The camera model's parameters checked before a camera is made of them.
#include <cmath>
#include <string>

#include "slicecap/hal/model_camera.hpp"

namespace slicecap::hal {

bool SensorModel::isValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!(framePeriodUs >= 1000.0 && framePeriodUs <= 1e6))
    return fail("frame period " + std::to_string(framePeriodUs) + " us is outside 1000..1e6");
  if (!(lineTimeUs >= 0.0 && lineTimeUs <= framePeriodUs))
    return fail("line time " + std::to_string(lineTimeUs) + " us is outside 0..the frame period");
  if (!(deliveryLatencyUs >= 0.0 && deliveryLatencyUs <= 1e6))
    return fail("delivery latency " + std::to_string(deliveryLatencyUs) + " us is outside 0..1e6");
  if (controlDelayFrames < 0 || controlDelayFrames > 64)
    return fail("control delay of " + std::to_string(controlDelayFrames) + " frames is outside 0..64");
  if (!(dropProbability >= 0.0 && dropProbability < 1.0))
    return fail("drop probability " + std::to_string(dropProbability) + " is outside [0, 1)");
  for (double g : colourGains)
    if (!(g > 0.0 && g < 16.0)) return fail("a colour gain is outside (0, 16)");
  if (!(readNoise >= 0.0 && readNoise < 0.5)) return fail("read noise is outside [0, 0.5)");
  if (!(fullWellElectrons >= 0.0)) return fail("full well is negative");
  if (!(autoExposureUs > 0.0 && autoExposureUs <= framePeriodUs))
    return fail("auto exposure " + std::to_string(autoExposureUs) + " us is outside (0, period]");
  if (!(autoGain >= 1.0 && autoGain <= maxGain)) return fail("auto gain is outside 1..max gain");
  if (std::string why; !RoomFlicker{flickerHz, flickerDepth, 0.0}.isValid(&why)) return fail(why);
  if (std::string why; !isp.isValid(&why)) return fail(why);
  if (rawFormat) {
    if (!bayerFormatFromLibcameraName(bayerFormatName(*rawFormat)))
      return fail("RAW format " + bayerFormatName(*rawFormat) + " is not one the decoder reads");
    const double largest16 = std::ldexp(double((1 << rawFormat->bitDepth) - 1), 16 - rawFormat->bitDepth);
    if (!(rawBlackLevel16 >= 0.0 && rawBlackLevel16 < largest16))
      return fail("RAW black level " + std::to_string(rawBlackLevel16) + " is outside 0..full scale");
  }
  return true;
}

}  // namespace slicecap::hal
