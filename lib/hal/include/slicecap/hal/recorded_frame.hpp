// A recording's frame entries and a live frame's metadata, each made from the other in one place
// (the file camera, `slicecap process` and the daemon's recorder).
#pragma once

#include <cstdint>
#include <optional>

#include "slicecap/hal/frame.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::hal {

/// \brief A recorded frame's metadata with its times moved by `shiftUs` (a looped or continued
/// recording's time line); `sequence` is the caller's count.
FrameMetadata metadataOf(const io::RecordedFrame& entry, std::uint64_t sequence,
                         std::int64_t shiftUs = 0);

/// \brief Sets `frame`'s encoding and black16 to what `recording` says its frames hold (a RAW
/// sweep's linear16 frames: the decoding's black16).
void setRecordedEncoding(Frame& frame, const io::Recording& recording);

/// \brief A frame's LED exposure as a recording keeps it, its times moved by `shiftUs`.
std::optional<io::RecordedLedExposure> recordedLedExposure(const FrameMetadata& metadata,
                                                           std::int64_t shiftUs = 0);

}  // namespace slicecap::hal
