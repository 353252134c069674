// The libcamera camera's buffers and frames: dmabufs mapped, RAW mosaics decoded with the frame's
// black levels, processed planes viewed, and each frame's metadata read.
#include <libcamera/control_ids.h>

#include <cerrno>
#include <cstdlib>

#include "libcamera_compat.hpp"
#include "libcamera_state.hpp"

namespace slicecap::hal {

using namespace libcamera_parts;

void LibcameraCamera::State::mapBuffers(libcamera::Stream* stream) {
  std::map<int, Mapping> byDescriptor;
  for (const std::unique_ptr<libcamera::FrameBuffer>& buffer : allocator->buffers(stream)) {
    std::vector<std::span<const std::uint8_t>> spans;
    for (const libcamera::FrameBuffer::Plane& plane : buffer->planes()) {
      const int fd = plane.fd.get();
      auto found = byDescriptor.find(fd);
      if (found == byDescriptor.end()) {
        Mapping mapping;
        mapping.length = static_cast<std::size_t>(::lseek(fd, 0, SEEK_END));
        mapping.start = ::mmap(nullptr, mapping.length, PROT_READ, MAP_SHARED, fd, 0);
        if (mapping.start == MAP_FAILED) fail("cannot map a frame buffer", -errno);
        mappings.push_back(mapping);
        found = byDescriptor.emplace(fd, mapping).first;
      }
      const std::size_t offset =
          plane.offset == libcamera::FrameBuffer::Plane::kInvalidOffset ? 0 : plane.offset;
      if (offset + plane.length > found->second.length)
        throw CameraError(name() + ": a buffer plane lies outside its dmabuf");
      spans.emplace_back(static_cast<const std::uint8_t*>(found->second.start) + offset,
                         plane.length);
    }
    planes[buffer.get()] = std::move(spans);
  }
}

void LibcameraCamera::State::unmapBuffers() {
  for (const Mapping& mapping : mappings) ::munmap(mapping.start, mapping.length);
  mappings.clear();
  planes.clear();
}

BayerFrameView LibcameraCamera::State::mosaicOf(const libcamera::FrameBuffer& buffer) const {
  const std::vector<std::span<const std::uint8_t>>& spans = planes.at(&buffer);
  BayerFrameView mosaic;
  mosaic.format = *bayer;
  mosaic.widthPx = int(rawSize.width);
  mosaic.heightPx = int(rawSize.height);
  mosaic.strideBytes = strideBytes;
  if (!spans.empty()) mosaic.bytes = spans[0];
  return mosaic;
}

BayerBlackLevels LibcameraCamera::State::blackLevelsOf(const libcamera::ControlList& reported) {
  if (const auto levels = libcamera_compat::sensorBlackLevels(reported)) return {*levels};
  warnOnce(name() + " reports no SensorBlackLevels with its RAW frames: a black level of " +
           std::to_string(int(kDefaultBlackLevel16)) +
           " of 65535 (64 at 10 bits, Raspberry Pi's default) is assumed");
  return BayerBlackLevels::uniform(kDefaultBlackLevel16);
}

RawFrameView LibcameraCamera::State::viewOf(const libcamera::FrameBuffer& buffer) const {
  const std::vector<std::span<const std::uint8_t>>& spans = planes.at(&buffer);
  RawFrameView raw;
  raw.layout = layout;
  raw.yuv = yuv;
  raw.widthPx = config.widthPx;
  raw.heightPx = config.heightPx;
  raw.strideBytes[0] = strideBytes;
  if (layout == RawLayout::Yuv420) {
    const std::size_t chromaStride = strideBytes / 2;
    const std::size_t lumaBytes = strideBytes * std::size_t(config.heightPx);
    const std::size_t chromaBytes = chromaStride * std::size_t((config.heightPx + 1) / 2);
    raw.strideBytes[1] = raw.strideBytes[2] = chromaStride;
    if (spans.size() >= 3) {
      for (int plane = 0; plane < 3; ++plane) raw.planes[plane] = spans[plane];
    } else if (!spans.empty() && spans[0].size() >= lumaBytes + 2 * chromaBytes) {
      raw.planes[0] = spans[0].subspan(0, lumaBytes);
      raw.planes[1] = spans[0].subspan(lumaBytes, chromaBytes);
      raw.planes[2] = spans[0].subspan(lumaBytes + chromaBytes, chromaBytes);
    }
  } else if (!spans.empty()) {
    raw.planes[0] = spans[0];
  }
  return raw;
}

void LibcameraCamera::State::describeFrame(Frame& frame, const libcamera::Request* request,
                                           const libcamera::FrameMetadata& metadata,
                                           const libcamera::ControlList& reported) {
  if (!firstSequence) firstSequence = metadata.sequence;
  frame.encoding = bayer ? PixelEncoding::Linear16 : PixelEncoding::Srgb8;
  frame.metadata.sequence = metadata.sequence - *firstSequence;
  // The sensor's timestamp where the pipeline reports it (the Pi: the start of row 0's readout,
  // picamera2 issue 821), else the buffer's.
  const std::int64_t timestampNs = reported.get(libcamera::controls::SensorTimestamp)
                                       .value_or(static_cast<std::int64_t>(metadata.timestamp));
  frame.metadata.timestampUs = timestampNs / 1000;
  const auto carried = locksCarried.find(request);
  frame.metadata.exposureLocks = carried == locksCarried.end() ? 0 : carried->second;
  // A pipeline that reports no exposure (libcamera's uvcvideo reports only the timestamp): the
  // lock this frame's request carried when it is the one in force, the configuration when no
  // lock was made, else unknown (0).
  std::optional<ExposureSetting> known;
  if (frame.metadata.exposureLocks == 0)
    known = ExposureSetting{config.exposureUs.value_or(0.0), config.gain};
  else if (frame.metadata.exposureLocks == locks)
    known = lockedExposure;
  frame.metadata.exposureUs = reported.get(libcamera::controls::ExposureTime)
                                  .value_or(known ? known->exposureUs : 0.0);
  frame.metadata.gain =
      double(reported.get(libcamera::controls::AnalogueGain)
                 .value_or(static_cast<float>(known ? known->gain.value_or(1.0) : 1.0))) *
      double(reported.get(libcamera::controls::DigitalGain).value_or(1.0f));
  // The duration the frame ran at (the Pi's IPA reports FrameDuration with every frame): a
  // pinned one the sensor did not hold leaves the room light's flicker in the subtraction.
  if (const auto durationUs = reported.get(libcamera::controls::FrameDuration);
      durationUs && frameDurationLimitsUs && std::abs(*durationUs - *frameDurationLimitsUs) > 1)
    warnOnce(name() + " runs frames of " + std::to_string(*durationUs) + " us, not the " +
             std::to_string(*frameDurationLimitsUs) +
             " us pinned by mains_hz (FrameDurationLimits): the room light's flicker is not "
             "hidden");
  // Row 0 began exposing one exposure before its readout; only where the pipeline says both
  // (a timestamp without a reported exposure, as uvcvideo's, marks nothing known).
  if (const auto exposureUs = reported.get(libcamera::controls::ExposureTime);
      exposureUs && reported.get(libcamera::controls::SensorTimestamp))
    frame.metadata.exposureStartUs = frame.metadata.timestampUs - std::int64_t(*exposureUs);
}

}  // namespace slicecap::hal
