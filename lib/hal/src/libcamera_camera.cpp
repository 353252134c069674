// libcamera capture: the camera acquired through the shared CameraManager, locked controls, and
// completed requests handed from libcamera's thread to the caller through an eventfd and queued
// again. Stream choice: libcamera_configure.cpp; buffers and frames: libcamera_frames.cpp.
#include <libcamera/control_ids.h>
#include <poll.h>
#include <sys/eventfd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <stdexcept>

#include "libcamera_state.hpp"

namespace slicecap::hal {

using namespace libcamera_parts;

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
  state_->describeFrame(frame, request, metadata, reported);
  return {CaptureResult::Status::Frame, std::move(frame), ""};
}

}  // namespace slicecap::hal
