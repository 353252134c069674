// libcamera capture: one shared CameraManager, locked controls, mapped dmabufs, and completed
// requests handed from libcamera's thread to the caller through an eventfd.
#include "slicecap/hal/libcamera_camera.hpp"

#include <libcamera/camera_manager.h>
#include <libcamera/control_ids.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/request.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <unordered_map>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>

#include <iostream>
#include <set>

#include "libcamera_compat.hpp"
#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/raw_frame.hpp"

namespace slicecap::hal {
namespace {

// The manager and its users, counted under one lock: a new manager is made only after the last
// user has destroyed the old one (a weak_ptr would expire before its deleter finished, and a
// second manager made in that moment aborts the process).
std::mutex managerMutex;
libcamera::CameraManager* managerInstance = nullptr;
std::size_t managerUsers = 0;

void releaseCameraManager(libcamera::CameraManager*) {
  const std::lock_guard lock(managerMutex);
  if (--managerUsers > 0) return;
  managerInstance->stop();
  delete managerInstance;
  managerInstance = nullptr;
}

/// The process's one CameraManager, alive while any camera (or listing) holds it.
std::shared_ptr<libcamera::CameraManager> sharedCameraManager() {
  const std::lock_guard lock(managerMutex);
  if (managerInstance == nullptr) {
    auto manager = std::make_unique<libcamera::CameraManager>();
    if (const int result = manager->start(); result != 0)
      throw CameraError(std::string("libcamera: cannot start the camera manager: ") +
                        std::strerror(-result));
    managerInstance = manager.release();
  }
  ++managerUsers;
  return std::shared_ptr<libcamera::CameraManager>(managerInstance, releaseCameraManager);
}

struct FormatChoice {
  libcamera::PixelFormat format;
  RawLayout layout;
};

/// libcamera names formats by DRM fourcc (little-endian words): RGB888 is B,G,R in memory.
const FormatChoice kFormats[] = {{libcamera::formats::YUYV, RawLayout::Yuyv},
                                 {libcamera::formats::BGR888, RawLayout::Rgb24},
                                 {libcamera::formats::RGB888, RawLayout::Bgr24},
                                 {libcamera::formats::XRGB8888, RawLayout::Bgrx32},
                                 {libcamera::formats::YUV420, RawLayout::Yuv420}};

std::optional<RawLayout> layoutOf(const libcamera::PixelFormat& format) {
  for (const FormatChoice& choice : kFormats)
    if (choice.format == format) return choice.layout;
  return std::nullopt;
}

/// Says `message` on stderr the first time this process meets it: a camera reconfigured for
/// every sweep would otherwise repeat it every sweep.
void warnOnce(const std::string& message) {
  static std::mutex mutex;
  static std::set<std::string> said;
  const std::lock_guard lock(mutex);
  if (said.insert(message).second) std::cerr << "slicecap: " << message << "\n";
}

/// What trying the RAW stream came to: configured (`configuration` set), or not, with `reason`
/// empty when the camera offers no RAW stream at all and naming the format when it offers one
/// slicecap does not decode.
struct RawAttempt {
  std::unique_ptr<libcamera::CameraConfiguration> configuration;
  std::optional<BayerFormat> format;
  std::string reason;
};

struct Mapping {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

// Auto exposure off, and the exposure time and analogue gain that are given: at start from the
// configuration, and on every request after Camera::lockExposure.
void setManualExposure(libcamera::ControlList& controls, std::optional<double> exposureUs,
                       std::optional<double> gain) {
  controls.set(libcamera::controls::AeEnable, false);
  if (exposureUs)
    controls.set(libcamera::controls::ExposureTime,
                 static_cast<std::int32_t>(std::clamp(*exposureUs, 1.0, 2147483647.0)));
  if (gain) controls.set(libcamera::controls::AnalogueGain, static_cast<float>(*gain));
}

// A stream configuration's formats with their discrete sizes (a RAW format's sizes are the
// sensor's modes: picamera2's Picamera2.sensor_modes reads them the same way, from the Raw role).
std::vector<OfferedFormat> offeredFormatsOf(const libcamera::StreamConfiguration& stream) {
  std::vector<OfferedFormat> offered;
  for (const libcamera::PixelFormat& format : stream.formats().pixelformats()) {
    std::vector<std::pair<int, int>> sizes;
    for (const libcamera::Size& size : stream.formats().sizes(format))
      sizes.emplace_back(int(size.width), int(size.height));
    offered.push_back(offeredFormat(format.toString(), std::move(sizes)));
  }
  return offered;
}

}  // namespace

std::vector<std::string> listLibcameraCameras() {
  const std::shared_ptr<libcamera::CameraManager> manager = sharedCameraManager();
  std::vector<std::string> ids;
  for (const std::shared_ptr<libcamera::Camera>& camera : manager->cameras())
    ids.push_back(camera->id());
  return ids;
}

std::vector<CameraModes> listLibcameraModes() {
  const std::shared_ptr<libcamera::CameraManager> manager = sharedCameraManager();
  std::vector<CameraModes> cameras;
  for (const std::shared_ptr<libcamera::Camera>& camera : manager->cameras()) {
    CameraModes modes;
    modes.id = "libcamera: " + camera->id();
    // generateConfiguration needs no acquire: a camera another process holds still lists.
    // The Raw role lists the sensor's RAW formats and modes; the processed formats come from
    // the role the sweep uses without RAW.
    if (auto raw = libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::Raw);
        raw && !raw->empty()) {
      for (OfferedFormat& format : offeredFormatsOf(raw->at(0)))
        if (format.raw) modes.formats.push_back(std::move(format));
      if (isRawFormatName(raw->at(0).pixelFormat.toString()))
        modes.proposedRawFormat = raw->at(0).pixelFormat.toString();
    }
    if (auto video = libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::VideoRecording);
        video && !video->empty())
      for (OfferedFormat& format : offeredFormatsOf(video->at(0)))
        if (!format.raw) modes.formats.push_back(std::move(format));
    cameras.push_back(std::move(modes));
  }
  return cameras;
}

struct LibcameraCamera::State {
  // Declared first so it is destroyed last: cameras must go before their manager.
  std::shared_ptr<libcamera::CameraManager> manager;
  std::shared_ptr<libcamera::Camera> camera;
  bool acquired = false;
  std::unique_ptr<libcamera::CameraConfiguration> configuration;
  std::unique_ptr<libcamera::FrameBufferAllocator> allocator;
  std::vector<std::unique_ptr<libcamera::Request>> requests;
  std::vector<Mapping> mappings;
  std::map<const libcamera::FrameBuffer*, std::vector<std::span<const std::uint8_t>>> planes;
  CameraConfig config;
  RawLayout layout = RawLayout::Yuyv;
  std::optional<BayerFormat> bayer;  // RAW: frames are decoded mosaics of rawSize
  libcamera::Size rawSize;
  std::size_t strideBytes = 0;
  bool configured = false;
  bool streaming = false;
  std::optional<std::uint32_t> firstSequence;
  std::optional<ExposureSetting> lockedExposure;  // set on every request queued from then on
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

  void mapBuffers(libcamera::Stream* stream) {
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

  void unmapBuffers() {
    for (const Mapping& mapping : mappings) ::munmap(mapping.start, mapping.length);
    mappings.clear();
    planes.clear();
  }

  /// The RAW stream alone (the ISP is not needed: the sensor's samples are decoded here), in a
  /// format decodeBayer reads, at the sensor mode whose binned size best fits the request.
  RawAttempt tryRaw(const CameraConfig& wanted) {
    RawAttempt attempt;
    auto generated = libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::Raw);
    if (!generated || generated->empty()) return attempt;
    libcamera::StreamConfiguration& stream = generated->at(0);
    // A pipeline without RAW (uvcvideo) answers the Raw role with its processed formats: then
    // no RAW is offered and nothing is said.
    const std::vector<OfferedFormat> offered = offeredFormatsOf(stream);
    if (std::none_of(offered.begin(), offered.end(), [](const OfferedFormat& f) { return f.raw; }))
      return attempt;
    const RawStreamChoice choice =
        chooseRawStream(offered, stream.pixelFormat.toString(), wanted.widthPx, wanted.heightPx);
    if (choice.format.empty()) {
      attempt.reason = choice.reason;
      return attempt;
    }
    // The offered PixelFormat whose name was chosen (the choice is made on names, shared with
    // the hardware check).
    libcamera::PixelFormat chosen;
    for (const libcamera::PixelFormat& format : stream.formats().pixelformats())
      if (format.toString() == choice.format) chosen = format;
    const std::pair<int, int> mode = choice.modePx;
    stream.pixelFormat = chosen;
    stream.size = libcamera::Size(unsigned(mode.first), unsigned(mode.second));
    stream.bufferCount = static_cast<unsigned>(std::max(wanted.bufferCount, 2));
    // No flips: a transform would also change the CFA order of the samples.
    libcamera_compat::keepSensorOrientation(*generated);
    if (generated->validate() == libcamera::CameraConfiguration::Invalid) {
      attempt.reason = "libcamera refused the RAW stream " + stream.toString() +
                       ": the processed stream is used instead";
      return attempt;
    }
    const std::string validated = stream.pixelFormat.toString();
    attempt.format = bayerFormatFromLibcameraName(validated);
    if (!attempt.format) {
      attempt.reason = undecodableRawReason(validated);
      return attempt;
    }
    attempt.configuration = std::move(generated);
    return attempt;
  }

  BayerFrameView mosaicOf(const libcamera::FrameBuffer& buffer) const {
    const std::vector<std::span<const std::uint8_t>>& spans = planes.at(&buffer);
    BayerFrameView mosaic;
    mosaic.format = *bayer;
    mosaic.widthPx = int(rawSize.width);
    mosaic.heightPx = int(rawSize.height);
    mosaic.strideBytes = strideBytes;
    if (!spans.empty()) mosaic.bytes = spans[0];
    return mosaic;
  }

  /// The frame's own black levels (SensorBlackLevels, which the Pi's IPA reports with every
  /// frame), else Raspberry Pi's default, said once.
  BayerBlackLevels blackLevelsOf(const libcamera::ControlList& reported) {
    if (const auto levels = libcamera_compat::sensorBlackLevels(reported)) return {*levels};
    warnOnce(name() + " reports no SensorBlackLevels with its RAW frames: a black level of " +
             std::to_string(int(kDefaultBlackLevel16)) +
             " of 65535 (64 at 10 bits, Raspberry Pi's default) is assumed");
    return BayerBlackLevels::uniform(kDefaultBlackLevel16);
  }

  RawFrameView viewOf(const libcamera::FrameBuffer& buffer) const {
    const std::vector<std::span<const std::uint8_t>>& spans = planes.at(&buffer);
    RawFrameView raw;
    raw.layout = layout;
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
};

LibcameraCamera::LibcameraCamera(const std::string& cameraId) : state_(std::make_unique<State>()) {
  state_->manager = sharedCameraManager();
  if (cameraId.empty()) {
    const std::vector<std::shared_ptr<libcamera::Camera>> cameras = state_->manager->cameras();
    if (cameras.empty())
      throw CameraError("libcamera: no camera found (is the camera connected and enabled in "
                        "config.txt? `cam --list` lists what libcamera sees)");
    state_->camera = cameras.front();
  } else {
    state_->camera = state_->manager->get(cameraId);
    if (!state_->camera)
      throw CameraError("libcamera: no camera with id '" + cameraId + "'");
  }
  if (const int result = state_->camera->acquire(); result != 0)
    state_->fail("cannot acquire it (in use by another program?)", result);
  state_->acquired = true;
  state_->readyFd = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK | EFD_SEMAPHORE);
  if (state_->readyFd < 0) state_->fail("cannot create an eventfd", -errno);
}

LibcameraCamera::~LibcameraCamera() {
  stop();
  if (state_->acquired) state_->camera->release();
  state_->configuration.reset();
  state_->camera.reset();
  if (state_->readyFd >= 0) ::close(state_->readyFd);
}

std::string LibcameraCamera::id() const { return state_->camera->id(); }

ConfigResult LibcameraCamera::configure(CameraConfig& config) {
  if (state_->streaming) throw std::logic_error("LibcameraCamera::configure while streaming");
  config.rawFormat.clear();
  state_->bayer.reset();
  std::vector<std::string> adjustments;
  if (config.raw != RawCapture::Off) {
    RawAttempt raw = state_->tryRaw(config);
    if (raw.configuration) {
      // A pipeline that validates a RAW-only configuration may still refuse to apply it.
      const int result = state_->camera->configure(raw.configuration.get());
      if (result == 0) return configureRaw(config, std::move(raw.configuration), *raw.format);
      raw.reason = "libcamera could not apply the RAW stream " +
                   raw.configuration->at(0).toString() + " (" + std::strerror(-result) +
                   "): the processed stream is used instead";
    }
    if (config.raw == RawCapture::On) {
      // The same cause, without the fallback that `on` refuses.
      std::string cause = raw.reason.empty() ? std::string("it offers no RAW stream") : raw.reason;
      if (const auto fallback = cause.find(": the processed stream is used instead");
          fallback != std::string::npos)
        cause.erase(fallback);
      return {ConfigResult::Status::Invalid,
              state_->name() + ": camera_raw = on, but " + cause +
                  " (camera_raw = auto takes the processed stream instead)"};
    }
    if (!raw.reason.empty()) {
      // Said once on stderr and in every sweep's configuration result (the session's journal).
      warnOnce(state_->name() + ": " + raw.reason);
      adjustments.push_back(raw.reason);
    }
  }
  state_->configuration = libcamera_compat::generateConfiguration(
      *state_->camera, libcamera::StreamRole::VideoRecording);
  if (!state_->configuration || state_->configuration->empty())
    return {ConfigResult::Status::Invalid, state_->name() + " offers no video stream"};
  libcamera::StreamConfiguration& stream = state_->configuration->at(0);
  const std::vector<libcamera::PixelFormat> offered = stream.formats().pixelformats();
  std::optional<libcamera::PixelFormat> chosen;
  for (const FormatChoice& choice : kFormats) {
    if (std::find(offered.begin(), offered.end(), choice.format) != offered.end()) {
      chosen = choice.format;
      break;
    }
  }
  if (!chosen)
    return {ConfigResult::Status::Invalid,
            state_->name() + " offers none of YUYV, BGR888, RGB888, XRGB8888, YUV420"};
  stream.pixelFormat = *chosen;
  stream.size = libcamera::Size(static_cast<unsigned>(config.widthPx),
                                static_cast<unsigned>(config.heightPx));
  stream.bufferCount = static_cast<unsigned>(std::max(config.bufferCount, 2));
  libcamera_compat::keepSensorOrientation(*state_->configuration);

  switch (state_->configuration->validate()) {
    case libcamera::CameraConfiguration::Invalid:
      return {ConfigResult::Status::Invalid,
              state_->name() + " cannot deliver " + stream.toString()};
    case libcamera::CameraConfiguration::Adjusted:
      adjustments.push_back("libcamera adjusted the stream to " + stream.toString());
      break;
    case libcamera::CameraConfiguration::Valid:
      break;
  }
  const std::optional<RawLayout> layout = layoutOf(stream.pixelFormat);
  if (!layout)
    return {ConfigResult::Status::Invalid,
            state_->name() + " changed the format to " + stream.pixelFormat.toString() +
                ", which slicecap cannot read"};
  if (const int result = state_->camera->configure(state_->configuration.get()); result != 0)
    state_->fail("cannot apply the configuration " + stream.toString(), result);

  config.widthPx = static_cast<int>(stream.size.width);
  config.heightPx = static_cast<int>(stream.size.height);
  config.bufferCount = static_cast<int>(stream.bufferCount);
  if (config.encoding != PixelEncoding::Srgb8) {
    adjustments.push_back("encoding linear16 -> srgb8 (processed streams are 8-bit)");
    config.encoding = PixelEncoding::Srgb8;
  }
  state_->layout = *layout;
  state_->strideBytes = stream.stride;
  state_->config = config;
  state_->configured = true;
  return ConfigResult::fromAdjustments(adjustments);
}

ConfigResult LibcameraCamera::configureRaw(
    CameraConfig& config, std::unique_ptr<libcamera::CameraConfiguration> configuration,
    const BayerFormat& format) {
  const libcamera::StreamConfiguration& stream = configuration->at(0);
  std::vector<std::string> adjustments;
  const int width = int(stream.size.width) / 2, height = int(stream.size.height) / 2;
  if (width != config.widthPx || height != config.heightPx)
    adjustments.push_back("size " + std::to_string(config.widthPx) + "x" +
                          std::to_string(config.heightPx) + " -> " + std::to_string(width) + "x" +
                          std::to_string(height) + " (RAW " + stream.toString() +
                          " binned 2 x 2)");
  if (config.encoding != PixelEncoding::Linear16)
    adjustments.push_back("encoding srgb8 -> linear16 (RAW " + bayerFormatName(format) + ")");
  config.widthPx = width;
  config.heightPx = height;
  config.encoding = PixelEncoding::Linear16;
  config.bufferCount = static_cast<int>(stream.bufferCount);
  config.rawFormat = bayerFormatName(format);
  state_->configuration = std::move(configuration);
  state_->bayer = format;
  state_->rawSize = stream.size;
  state_->strideBytes = stream.stride;
  state_->config = config;
  state_->configured = true;
  return ConfigResult::fromAdjustments(adjustments);
}

void LibcameraCamera::start() {
  if (!state_->configured) throw std::logic_error("LibcameraCamera::start before configure");
  if (state_->streaming) return;
  libcamera::Stream* stream = state_->configuration->at(0).stream();
  state_->allocator = std::make_unique<libcamera::FrameBufferAllocator>(state_->camera);
  if (const int result = state_->allocator->allocate(stream); result < 0)
    state_->fail("cannot allocate frame buffers", result);
  state_->mapBuffers(stream);
  for (const std::unique_ptr<libcamera::FrameBuffer>& buffer : state_->allocator->buffers(stream)) {
    std::unique_ptr<libcamera::Request> request = state_->camera->createRequest();
    if (!request) throw CameraError(state_->name() + ": cannot create a request");
    if (const int result = request->addBuffer(stream, buffer.get()); result != 0)
      state_->fail("cannot attach a buffer to a request", result);
    state_->requests.push_back(std::move(request));
  }

  // Locked for the whole sweep: the capture relates frames to each other and to the white
  // reference, which a drifting auto exposure or white balance would break.
  libcamera::ControlList controls;
  controls.set(libcamera::controls::AwbEnable, false);
  if (state_->config.exposureUs || state_->config.gain)
    setManualExposure(controls, state_->config.exposureUs, state_->config.gain);
  state_->camera->requestCompleted.connect(state_.get(), &State::onRequestCompleted);
  if (const int result = state_->camera->start(&controls); result != 0) {
    state_->camera->requestCompleted.disconnect(state_.get());
    state_->fail("cannot start", result);
  }
  state_->streaming = true;
  state_->firstSequence.reset();
  for (const std::unique_ptr<libcamera::Request>& request : state_->requests)
    if (const int result = state_->camera->queueRequest(request.get()); result != 0) {
      stop();
      state_->fail("cannot queue a request", result);
    }
}

ExposureLock LibcameraCamera::lockExposure(const ExposureSetting& wanted) {
  if (!state_->streaming) throw std::logic_error("LibcameraCamera::lockExposure before start");
  // Clamped to the ranges the camera reports, so the frames' metadata and the lock agree.
  const libcamera::ControlInfoMap& info = state_->camera->controls();
  // Without the control the request would drop it silently and the "lock" would lie.
  const auto exposureInfo = info.find(&libcamera::controls::ExposureTime);
  if (exposureInfo == info.end())
    return {std::nullopt, state_->name() + " has no ExposureTime control"};
  const double exposureUs =
      std::clamp<double>(wanted.exposureUs, exposureInfo->second.min().get<std::int32_t>(),
                         exposureInfo->second.max().get<std::int32_t>());
  // Nothing asked: the camera's default analogue gain where it says one, else unity.
  double gain = wanted.gain.value_or(1.0);
  if (const auto it = info.find(&libcamera::controls::AnalogueGain); it != info.end()) {
    if (!wanted.gain && !it->second.def().isNone()) gain = it->second.def().get<float>();
    gain = std::clamp<double>(gain, it->second.min().get<float>(), it->second.max().get<float>());
  }
  state_->lockedExposure = ExposureSetting{std::round(exposureUs), gain};
  ++state_->locks;
  return {state_->lockedExposure, ""};
}

void LibcameraCamera::stop() {
  if (!state_->streaming) return;
  state_->lockedExposure.reset();
  state_->locks = 0;
  state_->locksCarried.clear();
  state_->camera->stop();  // completes every pending request as cancelled, synchronously
  state_->camera->requestCompleted.disconnect(state_.get());
  state_->streaming = false;
  {
    const std::lock_guard lock(state_->completedMutex);
    state_->completed.clear();
  }
  std::uint64_t drained = 0;
  while (::read(state_->readyFd, &drained, sizeof drained) > 0) {
  }
  state_->requests.clear();
  state_->unmapBuffers();
  state_->allocator.reset();
}

std::optional<int> LibcameraCamera::readyDescriptor() const { return state_->readyFd; }

CaptureResult LibcameraCamera::nextFrame(std::chrono::milliseconds timeout) {
  if (!state_->streaming) throw std::logic_error("LibcameraCamera::nextFrame before start");
  pollfd ready{state_->readyFd, POLLIN, 0};
  if (::poll(&ready, 1, static_cast<int>(timeout.count())) <= 0)
    return {CaptureResult::Status::Timeout, std::nullopt, ""};
  std::uint64_t count = 0;
  if (::read(state_->readyFd, &count, sizeof count) <= 0)
    return {CaptureResult::Status::Timeout, std::nullopt, ""};
  libcamera::Request* request = nullptr;
  {
    const std::lock_guard lock(state_->completedMutex);
    if (state_->completed.empty()) return {CaptureResult::Status::Timeout, std::nullopt, ""};
    request = state_->completed.front();
    state_->completed.pop_front();
  }
  // The request goes back to the camera whatever happens to its frame below.
  struct Requeue {
    State& state;
    libcamera::Request* request;
    ~Requeue() {
      request->reuse(libcamera::Request::ReuseBuffers);  // also clears the request's controls
      if (state.lockedExposure)
        setManualExposure(request->controls(), state.lockedExposure->exposureUs,
                          state.lockedExposure->gain);
      state.locksCarried[request] = state.locks;
      if (state.streaming) state.camera->queueRequest(request);
    }
  } requeue{*state_, request};

  const libcamera::FrameBuffer* buffer = request->buffers().begin()->second;
  const libcamera::FrameMetadata& metadata = buffer->metadata();
  if (metadata.status != libcamera::FrameMetadata::FrameSuccess)
    return {CaptureResult::Status::Error, std::nullopt,
            state_->name() + ": frame " + std::to_string(metadata.sequence) + " failed"};
  const libcamera::ControlList& reported = request->metadata();
  Frame frame;
  try {
    if (state_->bayer) {
      frame.image = decodeBayer(state_->mosaicOf(*buffer), state_->blackLevelsOf(reported));
    } else {
      frame.image = toImage(state_->viewOf(*buffer));
    }
  } catch (const RawFrameError& error) {
    return {CaptureResult::Status::Error, std::nullopt,
            state_->name() + ": frame " + std::to_string(metadata.sequence) + ": " + error.what()};
  }
  if (!state_->firstSequence) state_->firstSequence = metadata.sequence;
  frame.encoding = state_->bayer ? PixelEncoding::Linear16 : PixelEncoding::Srgb8;
  frame.metadata.sequence = metadata.sequence - *state_->firstSequence;
  // The sensor's timestamp where the pipeline reports it (the Pi: the start of row 0's readout,
  // picamera2 issue 821), else the buffer's.
  const std::int64_t timestampNs = reported.get(libcamera::controls::SensorTimestamp)
                                       .value_or(static_cast<std::int64_t>(metadata.timestamp));
  frame.metadata.timestampUs = timestampNs / 1000;
  const auto carried = state_->locksCarried.find(request);
  frame.metadata.exposureLocks = carried == state_->locksCarried.end() ? 0 : carried->second;
  // A pipeline that reports no exposure (libcamera's uvcvideo reports only the timestamp): the
  // lock this frame's request carried when it is the one in force, the configuration when no
  // lock was made, else unknown (0).
  std::optional<ExposureSetting> known;
  if (frame.metadata.exposureLocks == 0)
    known = ExposureSetting{state_->config.exposureUs.value_or(0.0), state_->config.gain};
  else if (frame.metadata.exposureLocks == state_->locks)
    known = state_->lockedExposure;
  frame.metadata.exposureUs = reported.get(libcamera::controls::ExposureTime)
                                  .value_or(known ? known->exposureUs : 0.0);
  frame.metadata.gain =
      double(reported.get(libcamera::controls::AnalogueGain)
                 .value_or(static_cast<float>(known ? known->gain.value_or(1.0) : 1.0))) *
      double(reported.get(libcamera::controls::DigitalGain).value_or(1.0f));
  // Row 0 began exposing one exposure before its readout; only where the pipeline says both
  // (a timestamp without a reported exposure, as uvcvideo's, marks nothing known).
  if (const auto exposureUs = reported.get(libcamera::controls::ExposureTime);
      exposureUs && reported.get(libcamera::controls::SensorTimestamp))
    frame.metadata.exposureStartUs = frame.metadata.timestampUs - std::int64_t(*exposureUs);
  return {CaptureResult::Status::Frame, std::move(frame), ""};
}

}  // namespace slicecap::hal
