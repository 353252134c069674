// Room light's flicker: its mean over an exposure window, and the frame duration that hides it.
#include "slicecap/hal/room_flicker.hpp"

#include <cmath>
#include <numbers>

namespace slicecap::hal {

namespace {

// The phase in radians at `timeUs`, reduced to one cycle first: the steady clock's microseconds
// times 100 Hz are ~1e7 cycles after a day, whose fraction double still holds to 1e-9.
double radiansAt(const RoomFlicker& flicker, double timeUs) {
  const double cycles = flicker.hz * timeUs * 1e-6 + flicker.phaseCycles;
  return 2.0 * std::numbers::pi * (cycles - std::floor(cycles));
}

}  // namespace

double RoomFlicker::factorAt(double timeUs) const {
  if (hz <= 0.0 || depth <= 0.0) return 1.0;
  return 1.0 + depth * std::cos(radiansAt(*this, timeUs));
}

double RoomFlicker::meanFactor(double startUs, double durationUs) const {
  if (hz <= 0.0 || depth <= 0.0) return 1.0;
  const double spanRadians = 2.0 * std::numbers::pi * hz * durationUs * 1e-6;
  if (spanRadians < 1e-6) return factorAt(startUs + durationUs / 2);
  // The integral of cos over the window, divided by its length.
  const double start = radiansAt(*this, startUs);
  return 1.0 + depth * (std::sin(start + spanRadians) - std::sin(start)) / spanRadians;
}

bool RoomFlicker::isValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!(hz == 0.0 || (hz >= 1.0 && hz <= 1000.0)))
    return fail("flicker frequency " + std::to_string(hz) + " Hz is neither 0 nor in 1..1000");
  if (!(depth >= 0.0 && depth <= 1.0))
    return fail("flicker depth " + std::to_string(depth) + " is outside 0..1");
  if (!std::isfinite(phaseCycles)) return fail("flicker phase is not finite");
  return true;
}

double flickerHzOfMains(int mainsHz) {
  return 2.0 * mainsHz;
}

std::optional<double> frameDurationUsForMains(int mainsHz) {
  if (mainsHz <= 0) return std::nullopt;
  constexpr double kCameraFramePeriodUs = 1e6 / 30.0;
  const double periodUs = 1e6 / flickerHzOfMains(mainsHz);
  // The smallest whole number of periods not shorter than the camera's own 30 fps frame (a
  // tolerance for 4 x 8333.3 = 33333.3 us on 60 Hz).
  const double periods = std::ceil(kCameraFramePeriodUs / periodUs - 1e-9);
  return periods * periodUs;
}

}  // namespace slicecap::hal
