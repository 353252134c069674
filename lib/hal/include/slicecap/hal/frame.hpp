// A camera frame: the pixels and what the camera and the LED were doing when it was taken.
#pragma once

#include <cstdint>
#include <optional>

#include "slicecap/core/image.hpp"
#include "slicecap/core/pixel_encoding.hpp"
#include "slicecap/hal/led_exposure.hpp"

namespace slicecap::hal {

/// \brief What a frame was taken with. Real cameras report exposure and gain in their metadata
/// (libcamera's ExposureTime and AnalogueGain x DigitalGain controls); `ledOn` is filled by
/// whoever drives the LED (the session, from its strobe schedule; a recording, from its manifest).
struct FrameMetadata {
  std::uint64_t sequence = 0;    ///< counts from 0 at start(); gaps mean dropped frames
  std::int64_t timestampUs = 0;  ///< sensor timestamp (start of exposure), microseconds
  double exposureUs = 0.0;       ///< exposure time, microseconds
  double gain = 1.0;             ///< total gain (analogue x digital)
  bool ledOn = true;
  /// Camera::lockExposure calls since start() that this frame was taken under: its request
  /// carried the last of them (libcamera), or the driver no longer held frames from before it
  /// (V4L2). A frame taken before a lock reached the camera counts one less, whatever exposure
  /// it happens to report (an auto exposure can sit at the locked value by chance).
  std::uint32_t exposureLocks = 0;
  /// Start of row 0's exposure on the camera's clock, when the camera says when its frames were
  /// exposed: libcamera's SensorTimestamp is the start of the first row's readout, one exposure
  /// time after that row began (picamera2 issue 821), in CLOCK_MONOTONIC (libcamera bug 254);
  /// V4L2 says start of exposure or end of frame in its buffer flags. nullopt: unknown.
  std::optional<std::int64_t> exposureStartUs{};
  /// The sensor's rolling-shutter line time (row-to-row start delay), when the camera says it.
  std::optional<double> lineTimeUs{};
  /// What the LED did over this frame's rows, from the LED's timeline (the daemon's frame loop).
  /// nullopt: only `ledOn` is known (a recording without it, an offline run).
  std::optional<LedExposure> ledExposure{};
  /// The level of an HDR sweep's exposure cycle (0 = the longest) this frame was taken at: an HDR
  /// recording's frames[].exposure_level. nullopt: a sweep of one exposure.
  std::optional<int> exposureLevel{};
};

/// \brief One frame: gray or RGB samples in `encoding` (8-bit sRGB or 16-bit linear).
struct Frame {
  Image image;
  PixelEncoding encoding = PixelEncoding::Srgb8;
  FrameMetadata metadata;
  /// Linear16 only: the sample value of no light. A RAW frame's decode (decodeBayer) keeps the
  /// read noise below the sensor's black level above it (kDecodedBlack16), so a dark area's mean
  /// is not biased by clipping; linear16Value() takes it off. 0 for every other frame (a V4L2
  /// Y16 stream, a simulated or recorded one without it).
  std::uint16_t black16 = 0;
};

/// \brief A Linear16 sample of a frame whose black is `black16` as linear light, 1 = full scale
/// (65535): (sample - black16) / (65535 - black16), negative below black.
inline double linear16Value(std::uint16_t sample, std::uint16_t black16) {
  return (double(sample) - double(black16)) / (65535.0 - double(black16));
}

}  // namespace slicecap::hal
