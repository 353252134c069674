// The steady clock.
#include "slicecap/hal/clock.hpp"

#include <chrono>
#include <thread>

namespace slicecap::hal {

std::int64_t SteadyClock::nowUs() const {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void SteadyClock::sleepUntilUs(std::int64_t timeUs) {
  std::this_thread::sleep_until(
      std::chrono::steady_clock::time_point(std::chrono::microseconds(timeUs)));
}

}  // namespace slicecap::hal
