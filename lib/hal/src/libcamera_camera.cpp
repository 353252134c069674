// libcamera capture: the camera acquired through the shared CameraManager, locked controls, and
// completed requests handed from libcamera's thread to the caller through an eventfd and queued
// again. Stream choice: libcamera_configure.cpp; buffers and frames: libcamera_frames.cpp.
#include <libcamera/control_ids.h>
#include <poll.h>
#include <sys/eventfd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <stdexcept>

#include "libcamera_state.hpp"

namespace slicecap::hal {

using namespace libcamera_parts;

namespace {

/// Sets the ISP's adaptive processing off in `controls`, each control only where the camera
/// lists it (`offered`); returns the names of those it lacks. The processed stream is measured
/// through one response curve and a per-channel ratio to the white references in the same frame:
/// processing that changes with the image, the frame before or the white balance found would
/// change that ratio from frame to frame.
/// - AwbEnable off, with explicit ColourGains (1, 1): AWB turned off without gains freezes
///   whatever gains the IPA held (the Pi's Awb::disableAuto keeps its last, from its initialise
///   at 4000 K or an earlier run), which differ from one process or camera to the next. Unity
///   gains are the sensor's own channel balance, the same for every sweep; a per-channel gain
///   cancels in the window / white ratio anyway, so a neutral balance would buy nothing but a
///   scene-dependent setting. (The Pi's IPA derives the colour temperature for its colour matrix
///   and lens shading tables from the gains, ipa_base.cpp/awb.cpp setManualGains; unity gives
///   the same tables every sweep.)
/// - Sharpness 0: "no sharpening" (the Pi's sharpen algorithm, range 0..16, default 1): an edge
///   filter mixes the window with its neighbours.
/// - NoiseReductionMode off (controls::draft, the same name in Debian 12's 0.0.3 and the
///   Raspberry Pi fork): the Pi 5's denoise mode Off sets no temporal denoise (denoise.cpp
///   prepare), which otherwise blends the previous frame (the LED off) into this one.
std::vector<std::string> lockIspProcessing(libcamera::ControlList& controls,
                                           const libcamera::ControlInfoMap& offered) {
  std::vector<std::string> lacking;
  const auto has = [&offered, &lacking](const libcamera::ControlId& id) {
    if (offered.find(&id) != offered.end()) return true;
    lacking.push_back(id.name());
    return false;
  };
  if (has(libcamera::controls::AwbEnable)) controls.set(libcamera::controls::AwbEnable, false);
  if (has(libcamera::controls::ColourGains)) {
    const std::array<float, 2> unity{1.0f, 1.0f};  // red, blue
    controls.set(libcamera::controls::ColourGains, libcamera::Span<const float, 2>(unity));
  }
  if (has(libcamera::controls::Sharpness)) controls.set(libcamera::controls::Sharpness, 0.0f);
  if (has(libcamera::controls::draft::NoiseReductionMode))
    controls.set(libcamera::controls::draft::NoiseReductionMode,
                 static_cast<std::int32_t>(libcamera::controls::draft::NoiseReductionModeOff));
  return lacking;
}

}  // namespace

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
  const std::vector<std::string> lacking = lockIspProcessing(controls, state_->camera->controls());
  // RAW frames bypass the ISP: only the processed stream depends on these controls.
  if (!lacking.empty() && !state_->bayer) {
    std::string names;
    for (const std::string& control : lacking) names += (names.empty() ? "" : ", ") + control;
    warnOnce(state_->name() + " has no " + names +
             " control: its processed frames keep what the camera does there");
  }
  if (state_->config.exposureUs || state_->config.gain)
    setManualExposure(controls, state_->config.exposureUs, state_->config.gain);
  if (state_->frameDurationLimitsUs) setFrameDuration(controls, *state_->frameDurationLimitsUs);
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
  double exposureUs =
      std::clamp<double>(wanted.exposureUs, exposureInfo->second.min().get<std::int32_t>(),
                         exposureInfo->second.max().get<std::int32_t>());
  // Inside the pinned frame: the Pi's IPA would clamp it anyway (frame_timing.hpp), and the lock
  // must say what the frames will carry.
  const ExposureInFrame inFrame = clampExposureToFrame(exposureUs, state_->config.frameDurationUs);
  if (inFrame.note) warnOnce(state_->name() + ": " + *inFrame.note);
  exposureUs = inFrame.exposureUs;
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
      // On every request, as the locked exposure is: a pipeline that takes controls per request
      // keeps the frame pinned whichever request it runs.
      if (state.frameDurationLimitsUs)
        setFrameDuration(request->controls(), *state.frameDurationLimitsUs);
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
      frame.black16 = kDecodedBlack16;
    } else {
      frame.image = toImage(state_->viewOf(*buffer));
    }
  } catch (const RawFrameError& error) {
    return {CaptureResult::Status::Error, std::nullopt,
            state_->name() + ": frame " + std::to_string(metadata.sequence) + ": " + error.what()};
  }
  state_->describeFrame(frame, request, metadata, reported);
  return {CaptureResult::Status::Frame, std::move(frame), ""};
}

}  // namespace slicecap::hal
