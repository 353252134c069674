// The libcamera camera's private parts, shared by its files: the process's one CameraManager, the
// formats it reads, and the camera's state (libcamera_camera.cpp: requests and controls;
// libcamera_configure.cpp: stream choice; libcamera_frames.cpp: buffers and frame conversion).
#pragma once

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>
#include <libcamera/controls.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/request.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/frame_timing.hpp"
#include "slicecap/hal/libcamera_camera.hpp"
#include "slicecap/hal/raw_frame.hpp"

namespace slicecap::hal {
namespace libcamera_parts {

/// The process's one CameraManager, alive while any camera (or listing) holds it. Throws
/// CameraError when it cannot start.
std::shared_ptr<libcamera::CameraManager> sharedCameraManager();

struct FormatChoice {
  libcamera::PixelFormat format;
  RawLayout layout;
};

/// The processed formats slicecap reads, best first: RGB before YUV, because an RGB stream is
/// the ISP's R'G'B' itself (the Raspberry Pi pipelines give RGB streams the YUV colour space
/// with YcbcrEncoding None and full range, pipeline_base.cpp validateColorSpaces), while a YUV
/// one must be decoded by a matrix and range the camera has to report. libcamera names formats
/// by DRM fourcc (little-endian words): RGB888 is B,G,R in memory.
inline const FormatChoice kFormats[] = {{libcamera::formats::BGR888, RawLayout::Rgb24},
                                        {libcamera::formats::RGB888, RawLayout::Bgr24},
                                        {libcamera::formats::XRGB8888, RawLayout::Bgrx32},
                                        {libcamera::formats::YUYV, RawLayout::Yuyv},
                                        {libcamera::formats::YUV420, RawLayout::Yuv420}};

inline std::optional<RawLayout> layoutOf(const libcamera::PixelFormat& format) {
  for (const FormatChoice& choice : kFormats)
    if (choice.format == format) return choice.layout;
  return std::nullopt;
}

/// Says `message` on stderr the first time this process meets it: a camera reconfigured for
/// every sweep would otherwise repeat it every sweep.
void warnOnce(const std::string& message);

/// What trying the RAW stream came to: configured (`configuration` set), or not, with `reason`
/// empty when the camera offers no RAW stream at all and naming the format when it offers one
/// slicecap does not decode.
struct RawAttempt {
  std::unique_ptr<libcamera::CameraConfiguration> configuration;
  std::optional<BayerFormat> format;
  std::string reason;
  std::vector<std::string> notes;  ///< what validation changed on the way (RawStreamChoice)
};

/// Validates `configuration`'s one stream as a RAW request (camera_modes.hpp's RawValidator):
/// the format by libcamera's name, the mode, `bufferCount` buffers (2 at least), no flips.
/// Borrows `configuration`, which holds the last request validated.
RawValidator rawValidator(libcamera::CameraConfiguration& configuration, int bufferCount);

struct Mapping {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

// Auto exposure off, and the exposure time and analogue gain that are given: at start from the
// configuration, and on every request after Camera::lockExposure.
void setManualExposure(libcamera::ControlList& controls, std::optional<double> exposureUs,
                       std::optional<double> gain);

// FrameDurationLimits = {durationUs, durationUs} (microseconds, int64_t in Debian 12's 0.0.3 and
// the Raspberry Pi fork alike): the Pi's IPA takes it from the start controls and any request
// (ipa_base.cpp applyControls -> applyFrameDurations) and holds it until told otherwise.
void setFrameDuration(libcamera::ControlList& controls, std::int64_t durationUs);

// A stream configuration's formats with their discrete sizes (a RAW format's sizes are the
// sensor's modes: picamera2's Picamera2.sensor_modes reads them the same way, from the Raw role).
std::vector<OfferedFormat> offeredFormatsOf(const libcamera::StreamConfiguration& stream);

}  // namespace libcamera_parts

struct LibcameraCamera::State {
  // Declared first so it is destroyed last: cameras must go before their manager.
  std::shared_ptr<libcamera::CameraManager> manager;
  std::shared_ptr<libcamera::Camera> camera;
  bool acquired = false;
  std::unique_ptr<libcamera::CameraConfiguration> configuration;
  std::unique_ptr<libcamera::FrameBufferAllocator> allocator;
  std::vector<std::unique_ptr<libcamera::Request>> requests;
  std::vector<libcamera_parts::Mapping> mappings;
  std::map<const libcamera::FrameBuffer*, std::vector<std::span<const std::uint8_t>>> planes;
  CameraConfig config;
  RawLayout layout = RawLayout::Yuyv;
  std::optional<YuvEncoding> yuv;    // a YUV stream's matrix and range (its colour space)
  std::optional<BayerFormat> bayer;  // RAW: frames are decoded mosaics of rawSize
  libcamera::Size rawSize;
  std::size_t strideBytes = 0;
  bool configured = false;
  bool streaming = false;
  std::optional<std::uint32_t> firstSequence;
  std::optional<ExposureSetting> lockedExposure;  // set on every request queued from then on
  // FrameDurationLimits = {this, this} at start and on every request (mains_hz); nullopt: the
  // camera's own frame duration (not pinned, or the camera lacks the control).
  std::optional<std::int64_t> frameDurationLimitsUs;
  // Locks since start(), and how many of them each request carried when it was last queued: the
  // requests queued before a lock return frames taken under the setting before it.
  std::uint32_t locks = 0;
  std::unordered_map<const libcamera::Request*, std::uint32_t> locksCarried;
  int readyFd = -1;
  std::mutex completedMutex;
  std::deque<libcamera::Request*> completed;

  // Runs on libcamera's thread.
  void onRequestCompleted(libcamera::Request* request) {
    if (request->status() == libcamera::Request::RequestCancelled) return;
    {
      const std::lock_guard lock(completedMutex);
      completed.push_back(request);
    }
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t written = ::write(readyFd, &one, sizeof one);
  }

  std::string name() const { return "camera " + camera->id(); }

  [[noreturn]] void fail(const std::string& what, int negativeErrno) const {
    throw CameraError(name() + ": " + what + ": " + std::strerror(-negativeErrno));
  }

  /// Maps every buffer of `stream` (planes sharing a dmabuf share one mapping); CameraError
  /// naming the camera when a mapping fails.
  void mapBuffers(libcamera::Stream* stream);
  void unmapBuffers();
  /// The RAW stream alone (the ISP is not needed: the sensor's samples are decoded here), in a
  /// format decodeBayer reads, at the sensor mode whose binned size best fits the request.
  libcamera_parts::RawAttempt tryRaw(const CameraConfig& wanted);
  /// The processed stream in the first of kFormats the camera offers, at the size `cameraConfig`
  /// asks, applied and taken into `cameraConfig` (`adjustments`: those said so far). An Invalid
  /// result naming the camera when it offers no such stream or cannot deliver it; CameraError
  /// when it cannot apply one it validated.
  ConfigResult configureProcessed(CameraConfig& cameraConfig, std::vector<std::string> adjustments);
  /// After a stream is configured: the pinned frame duration planned against the range the
  /// camera now lists for FrameDurationLimits (the Pi's IPA sets it per sensor mode at configure,
  /// ipa_base.cpp), written back into `cameraConfig` with the exposure clamped inside it; returns
  /// what changed, for the configuration result.
  std::vector<std::string> pinFrameDuration(CameraConfig& cameraConfig);
  /// The RAW mosaic in `buffer` (configured RAW only).
  BayerFrameView mosaicOf(const libcamera::FrameBuffer& buffer) const;
  /// The frame's own black levels (SensorBlackLevels, which the Pi's IPA reports with every
  /// frame), else Raspberry Pi's default, said once.
  BayerBlackLevels blackLevelsOf(const libcamera::ControlList& reported);
  /// The processed frame's planes in `buffer`, in the configured layout.
  RawFrameView viewOf(const libcamera::FrameBuffer& buffer) const;
  /// The frame's sequence, timestamps, exposure and gain from the buffer's and the request's
  /// metadata (and the lock the request carried where the pipeline reports no exposure).
  void describeFrame(Frame& frame, const libcamera::Request* request,
                     const libcamera::FrameMetadata& metadata,
                     const libcamera::ControlList& reported);
};

}  // namespace slicecap::hal
