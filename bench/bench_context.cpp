// Context lines printed at the head of every benchmark's output: what the figures are comparable
// to, and how a Raspberry Pi owner measures the same figures natively (never from an emulated run).
#include <benchmark/benchmark.h>

namespace {

constexpr const char* kTarget =
#if defined(__aarch64__)
    "aarch64";
#elif defined(__x86_64__)
    "x86-64";
#else
    "other";
#endif

const bool kRegistered = [] {
  benchmark::AddCustomContext("slicecap_built_for", kTarget);
  benchmark::AddCustomContext(
      "slicecap_budgets",
      "stated as multiples of the development machine's figures (x86-64, one core: Method B "
      "~0.6 ms per RGB ABRDF from 168 samples, docs/results/2026-11-24-reconstruction-methods.md); a Pi 4 core is "
      "estimated, not measured, at 2-5x slower, so up to 5x those figures is within budget there");
  benchmark::AddCustomContext(
      "slicecap_reproduce_on_a_pi",
      "on the box itself (Raspberry Pi OS bookworm, aarch64): git clone, scripts/install-deps, "
      "then scripts/bench (builds bench/ natively, runs each program pinned to core 0); "
      "figures from qemu (scripts/arm64-check) are emulation, not Pi timings");
  return true;
}();

}  // namespace
