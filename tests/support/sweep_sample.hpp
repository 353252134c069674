// A sweep sample at a slice parameter, as the session-store tests record and replay them.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>

#include "slicecap/capture/frame_sample.hpp"

namespace slicecap::test {

/// \brief A grey sample of `value` at elevation 30/30, light azimuth `parameterDeg`, view 15 deg
/// beyond it, from frame `frame` (33 ms apart).
inline capture::FrameSample sampleAt(double parameterDeg, double value, std::uint64_t frame = 0) {
  return {std::int64_t(frame) * 33000,
          frame,
          {30, parameterDeg},
          {30, parameterDeg + 15},
          Rgb::gray(value)};
}

/// \brief sampleAt's sample from an HDR sweep's frame of exposure level `exposureLevel` and
/// exposure x gain `scale` (units per unit radiance): its 36 cells read `radiance` per unit
/// exposure (cell k: x (1 + 0.001 k)) on a sensor of full scale 1 that clips at 0.98, variance
/// (read 0.002 + shot) / scale^2, under irradiance 10; its value is this frame's alone.
inline capture::FrameSample hdrSampleAt(double parameterDeg, double radiance, double scale,
                                        int exposureLevel, std::uint64_t frame = 0) {
  capture::FrameSample s = sampleAt(parameterDeg, 0.0, frame);
  capture::HdrReading hdr;
  hdr.exposureLevel = exposureLevel;
  constexpr int kCells = capture::kHdrCellsPerSide * capture::kHdrCellsPerSide;
  for (int k = 0; k < kCells; ++k) {
    const double level = radiance * (1.0 + 0.001 * k) * scale;
    const double read = std::min(level, 1.0) / scale;  // a clipped cell reads full scale
    const double variance = (0.002 * 0.002 + std::min(level, 1.0) / 8000.0) / (scale * scale);
    hdr.cells.push_back(
        {Rgb::gray(read), Rgb::gray(variance), std::min(level, 1.0), level >= 0.98});
  }
  hdr.irradiance = Rgb::gray(10.0);
  hdr.irradianceWeight = scale;
  s.value = hdr.cells.front().radiance * (1.0 / 10.0);
  s.hdr = std::move(hdr);
  return s;
}

}  // namespace slicecap::test
