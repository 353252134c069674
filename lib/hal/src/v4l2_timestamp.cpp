// V4L2 buffer timestamp flags.
#include "slicecap/hal/v4l2_timestamp.hpp"

#include <linux/videodev2.h>

#include <cmath>

namespace slicecap::hal {

std::optional<std::int64_t> v4l2ExposureStartUs(std::uint32_t flags, std::int64_t timestampUs,
                                                double exposureUs, std::optional<double> readoutUs) {
  if ((flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) != V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
    return std::nullopt;
  const std::uint32_t source = flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK;
  if (source == V4L2_BUF_FLAG_TSTAMP_SRC_SOE) return timestampUs;
  if (source != V4L2_BUF_FLAG_TSTAMP_SRC_EOF) return std::nullopt;  // a source this code predates
  if (!(exposureUs > 0.0) || !readoutUs || !(*readoutUs >= 0.0)) return std::nullopt;
  return timestampUs - static_cast<std::int64_t>(std::llround(*readoutUs + exposureUs));
}

}  // namespace slicecap::hal
