// When a V4L2 frame began its exposure, from what its buffer's flags say its timestamp marks.
#pragma once

#include <cstdint>
#include <optional>

namespace slicecap::hal {

/// \brief Start of row 0's exposure on CLOCK_MONOTONIC (the clock of the LED's timeline), from a
/// dequeued buffer's `flags` and `timestampUs` (Linux media documentation, "struct v4l2_buffer",
/// buffer flags):
/// - the timestamp must be V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC; UNKNOWN (another clock, or none)
///   and COPY (copied from an output buffer) give nullopt;
/// - V4L2_BUF_FLAG_TSTAMP_SRC_SOE: taken when the exposure began: the timestamp itself;
/// - V4L2_BUF_FLAG_TSTAMP_SRC_EOF (the value 0, what a driver that says nothing says): taken when
///   the last pixel was received: minus the readout time and the exposure time, when both are
///   known (`exposureUs` > 0, `readoutUs` set), else nullopt.
std::optional<std::int64_t> v4l2ExposureStartUs(std::uint32_t flags, std::int64_t timestampUs,
                                                double exposureUs, std::optional<double> readoutUs);

}  // namespace slicecap::hal
