// Polling a condition another thread brings about, with a deadline: a test that waits without one
// hangs CI instead of failing when the condition never comes.
#pragma once

#include <chrono>
#include <thread>

namespace slicecap::test {

/// \brief Polls `condition` every millisecond until it holds (true) or `deadline` has passed
/// (false, after one last look).
template <class Condition>
bool waitUntil(Condition condition, std::chrono::milliseconds deadline = std::chrono::seconds(10)) {
  const auto end = std::chrono::steady_clock::now() + deadline;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return condition();
}

}  // namespace slicecap::test
