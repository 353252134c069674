// The room's light on the virtual rig, stated against the LED's (slicecapd's model_room_light,
// issue 44's rooms).
#pragma once

#include "slicecap/sim/rig.hpp"

namespace slicecap::sim {

/// \brief The diffuse room irradiance (W/m^2, RigParams::ambientIrradiance) that is
/// `fractionOfLed` of the LED's face-on irradiance at the rig's light distance: intensity / d^2,
/// the rig's radiometry.
inline double roomIrradianceFor(const RigParams& rig, double fractionOfLed) {
  const double lightDistanceM = rig.lightDistanceMm / 1000.0;
  return fractionOfLed * rig.ledIntensityWPerSr / (lightDistanceM * lightDistanceM);
}

}  // namespace slicecap::sim
