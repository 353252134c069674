// The V4L2 camera's frames: a dequeued buffer's bytes viewed in the configured layout, decoded
// (RAW Bayer, with the default black level: V4L2 reports none) or converted, and its metadata.
#include <algorithm>

#include "slicecap/hal/v4l2_timestamp.hpp"
#include "v4l2_state.hpp"

namespace slicecap::hal {

using namespace v4l2_parts;

CaptureResult V4l2Camera::State::frameOf(const v4l2_buffer& buffer, bool exposedBeforeLock) {
  if ((buffer.flags & V4L2_BUF_FLAG_ERROR) != 0)
    return {CaptureResult::Status::Error, std::nullopt,
            device + ": the driver marked frame " + std::to_string(buffer.sequence) +
                " as corrupted"};
  const MappedBuffer& mapped = buffers.at(buffer.index);
  RawFrameView raw;
  raw.layout = layout;
  raw.yuv = yuv;
  raw.widthPx = config.widthPx;
  raw.heightPx = config.heightPx;
  const std::size_t used = buffer.bytesused != 0 ? buffer.bytesused : mapped.length;
  const auto* bytes = static_cast<const std::uint8_t*>(mapped.start);
  if (raw.layout == RawLayout::Yuv420) {
    const std::size_t lumaBytes = strideBytes * std::size_t(raw.heightPx);
    const std::size_t chromaStride = strideBytes / 2;
    const std::size_t chromaBytes = chromaStride * std::size_t((raw.heightPx + 1) / 2);
    if (used < lumaBytes + 2 * chromaBytes)
      return {CaptureResult::Status::Error, std::nullopt,
              device + ": frame " + std::to_string(buffer.sequence) + " is truncated"};
    raw.planes[0] = {bytes, lumaBytes};
    raw.planes[1] = {bytes + lumaBytes, chromaBytes};
    raw.planes[2] = {bytes + lumaBytes + chromaBytes, chromaBytes};
    raw.strideBytes[0] = strideBytes;
    raw.strideBytes[1] = raw.strideBytes[2] = chromaStride;
  } else {
    raw.planes[0] = {bytes, std::min(used, mapped.length)};
    raw.strideBytes[0] = strideBytes;
  }
  Frame frame;
  try {
    if (bayer) {
      BayerFrameView mosaic;
      mosaic.format = *bayer;
      mosaic.widthPx = 2 * raw.widthPx;
      mosaic.heightPx = 2 * raw.heightPx;
      mosaic.bytes = raw.planes[0];
      mosaic.strideBytes = strideBytes;
      frame.image = decodeBayer(mosaic, BayerBlackLevels::uniform(kDefaultBlackLevel16));
      frame.black16 = kDecodedBlack16;
    } else {
      frame.image = toImage(raw);
    }
  } catch (const RawFrameError& error) {
    return {CaptureResult::Status::Error, std::nullopt,
            device + ": frame " + std::to_string(buffer.sequence) + ": " + error.what()};
  }
  describeFrame(frame, buffer, raw.layout, exposedBeforeLock);
  return {CaptureResult::Status::Frame, std::move(frame), ""};
}

void V4l2Camera::State::describeFrame(Frame& frame, const v4l2_buffer& buffer, RawLayout layoutRead,
                                      bool exposedBeforeLock) {
  if (!firstSequence) firstSequence = buffer.sequence;
  frame.encoding = bayer ? PixelEncoding::Linear16 : encodingOf(layoutRead);
  frame.metadata.sequence = buffer.sequence - *firstSequence;
  frame.metadata.timestampUs =
      std::int64_t(buffer.timestamp.tv_sec) * 1'000'000 + buffer.timestamp.tv_usec;
  frame.metadata.exposureUs = exposedBeforeLock ? exposureBeforeLockUs
                                                : config.exposureUs.value_or(0.0);
  frame.metadata.gain =
      exposedBeforeLock ? gainBeforeLock : config.gain.value_or(1.0);
  frame.metadata.exposureLocks = exposedBeforeLock ? locks - 1 : locks;
  // What the timestamp marks is in the buffer's flags; an exposure left to the camera (0) is
  // unknown, so an end-of-frame timestamp then says nothing about the start.
  frame.metadata.exposureStartUs =
      v4l2ExposureStartUs(buffer.flags, frame.metadata.timestampUs, frame.metadata.exposureUs,
                          config.readoutUs);
}

}  // namespace slicecap::hal
