// The V4L2 camera's private parts, shared by its files: the device's state and the ioctl helper
// (v4l2_camera.cpp: the device, buffers and dequeue; v4l2_configure.cpp: format choice;
// v4l2_controls.cpp: exposure and gain controls; v4l2_frames.cpp: frame conversion).
#pragma once

#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cstring>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/raw_frame.hpp"
#include "slicecap/hal/v4l2_camera.hpp"

namespace slicecap::hal {
namespace v4l2_parts {

/// ioctl, again while a signal interrupts it; -1 with errno on failure.
int retryIoctl(int fd, unsigned long request, void* argument);

struct MappedBuffer {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

}  // namespace v4l2_parts

struct V4l2Camera::State {
  std::string device;
  std::string card;
  int fd = -1;
  bool configured = false;
  bool streaming = false;
  CameraConfig config;
  RawLayout layout = RawLayout::Yuyv;
  std::optional<YuvEncoding> yuv;    // a YUV stream's matrix and range, as the driver says
  std::optional<BayerFormat> bayer;  // RAW: the mosaic is twice the frame's size
  std::size_t strideBytes = 0;
  std::size_t imageBytes = 0;
  std::vector<v4l2_parts::MappedBuffer> buffers;
  std::optional<std::uint32_t> firstSequence;
  // After lockExposure the driver still holds up to bufferCount frames exposed before it, and
  // the sensor takes the change at the next frame's start: frames dequeued before
  // `lockReachesFrame` carry the exposure and gain from before the lock (0 us: auto exposure).
  std::uint64_t dequeued = 0;
  std::uint64_t lockReachesFrame = 0;
  std::uint32_t locks = 0;  // since start()
  double exposureBeforeLockUs = 0.0;
  double gainBeforeLock = 1.0;
  std::uint32_t grantedBuffers = 0;  // what REQBUFS gave, which may exceed what was asked
  // The exposure and gain controls as they were before the first lock since start(), put back at
  // stop(): a lock lasts for the sweep, and the next one may be meant to run on auto.
  std::vector<std::pair<std::uint32_t, std::int32_t>> controlsBeforeLocks;
  std::optional<double> exposureUsBeforeLocks, gainBeforeLocks;

  [[noreturn]] void fail(const std::string& what, int error) const {
    throw CameraError(device + ": " + what + ": " + std::strerror(error));
  }

  std::optional<v4l2_queryctrl> queryControl(std::uint32_t id) const;
  std::optional<std::int32_t> getControl(std::uint32_t id) const;
  /// The exposure and gain controls as they are, to put back: the modes first, then a value only
  /// where its mode leaves it to the user (an auto mode owns its value; shutter priority keeps
  /// the exposure time manual).
  std::vector<std::pair<std::uint32_t, std::int32_t>> exposureControls() const;
  bool setControl(std::uint32_t id, std::int32_t value) const;
  /// Sets a control to `wanted` clamped and stepped to its range; returns the value set, or
  /// nullopt when the device lacks the control or refuses it.
  std::optional<std::int32_t> setRangedControl(std::uint32_t id, double wanted) const;
  /// Auto exposure off and the exposure set, clamped to the control's range; returns the
  /// exposure set in microseconds (V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us), or nullopt when the
  /// device has no manual exposure.
  std::optional<double> setManualExposureUs(double wantedUs) const;
  /// Auto gain off and the gain set (the device's own units), clamped to its range; returns the
  /// gain set, or nullopt when the device lacks the control or refuses it.
  std::optional<std::int32_t> setManualGain(double wanted) const;
  /// V4L2_CID_POWER_LINE_FREQUENCY for the mains (a UVC camera's anti-flicker: 50 / 60 Hz, or
  /// disabled for 0) where the device has the control; what it reads back is added to `said`.
  void setPowerLineFrequency(int mainsHz, std::string& said) const;
  void releaseBuffers();

  /// The frame in the dequeued `buffer`, decoded (RAW) or converted, with its metadata; an Error
  /// result naming the device and frame when the driver marked it or its bytes are short.
  CaptureResult frameOf(const v4l2_buffer& buffer, bool exposedBeforeLock);
  /// The frame's sequence, timestamps, exposure and gain (from before the lock while the frames
  /// exposed before it drain).
  void describeFrame(Frame& frame, const v4l2_buffer& buffer, RawLayout layoutRead,
                     bool exposedBeforeLock);
};

}  // namespace slicecap::hal
