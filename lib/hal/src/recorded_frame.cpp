// Recorded frame entries to live metadata and back.
#include "slicecap/hal/recorded_frame.hpp"

namespace slicecap::hal {

FrameMetadata metadataOf(const io::RecordedFrame& entry, std::uint64_t sequence,
                         std::int64_t shiftUs) {
  FrameMetadata m;
  m.sequence = sequence;
  m.timestampUs = entry.timestampUs + shiftUs;
  m.exposureUs = entry.exposureUs;
  m.gain = entry.gain;
  m.ledOn = entry.ledOn;
  m.exposureLevel = entry.exposureLevel;
  if (entry.ledExposure) {
    const io::RecordedLedExposure& recorded = *entry.ledExposure;
    LedExposure exposure;
    exposure.row0StartUs = recorded.row0StartUs + shiftUs;
    exposure.lineTimeUs = recorded.lineTimeUs;
    exposure.exposureUs = recorded.exposureUs;
    exposure.guardUs = recorded.guardUs;
    exposure.onAtStart = recorded.onAtStart;
    for (const auto& [timeUs, on] : recorded.changes) exposure.changes.push_back({timeUs + shiftUs, on});
    m.exposureStartUs = exposure.row0StartUs;
    m.ledExposure = std::move(exposure);
  }
  return m;
}

void setRecordedEncoding(Frame& frame, const io::Recording& recording) {
  frame.encoding = recording.encoding;
  frame.black16 = recording.encoding == PixelEncoding::Linear16 && recording.decoding
                      ? recording.decoding->black16
                      : 0;
}

std::optional<io::RecordedLedExposure> recordedLedExposure(const FrameMetadata& metadata,
                                                           std::int64_t shiftUs) {
  if (!metadata.ledExposure) return std::nullopt;
  const LedExposure& e = *metadata.ledExposure;
  io::RecordedLedExposure recorded;
  recorded.row0StartUs = e.row0StartUs + shiftUs;
  recorded.lineTimeUs = e.lineTimeUs;
  recorded.exposureUs = e.exposureUs;
  recorded.guardUs = e.guardUs;
  recorded.onAtStart = e.onAtStart;
  for (const LedChange& change : e.changes) recorded.changes.emplace_back(change.timeUs + shiftUs, change.on);
  return recorded;
}

}  // namespace slicecap::hal
