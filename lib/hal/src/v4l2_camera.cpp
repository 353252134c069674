// V4L2 capture: the device opened and checked, mmap buffers requested and queued, streaming
// started and stopped, frames dequeued on poll and queued again. Format choice:
// v4l2_configure.cpp; controls: v4l2_controls.cpp; frame conversion: v4l2_frames.cpp.
#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

#include "v4l2_state.hpp"

namespace slicecap::hal {
namespace v4l2_parts {

int retryIoctl(int fd, unsigned long request, void* argument) {
  int result = 0;
  do {
    result = ::ioctl(fd, request, argument);
  } while (result == -1 && errno == EINTR);
  return result;
}

}  // namespace v4l2_parts

using namespace v4l2_parts;

void V4l2Camera::State::releaseBuffers() {
  for (MappedBuffer& buffer : buffers)
    if (buffer.start != MAP_FAILED) ::munmap(buffer.start, buffer.length);
  buffers.clear();
  v4l2_requestbuffers request{};
  request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  request.memory = V4L2_MEMORY_MMAP;
  request.count = 0;
  retryIoctl(fd, VIDIOC_REQBUFS, &request);
}

V4l2Camera::V4l2Camera(const std::filesystem::path& device) : state_(std::make_unique<State>()) {
  state_->device = device.string();
  state_->fd = ::open(device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (state_->fd < 0) state_->fail("cannot open the camera", errno);
  v4l2_capability capability{};
  if (retryIoctl(state_->fd, VIDIOC_QUERYCAP, &capability) != 0) {
    const int error = errno;
    ::close(state_->fd);
    state_->fail("not a V4L2 device", error);
  }
  const std::uint32_t caps = (capability.capabilities & V4L2_CAP_DEVICE_CAPS) != 0
                                 ? capability.device_caps
                                 : capability.capabilities;
  state_->card = reinterpret_cast<const char*>(capability.card);
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    ::close(state_->fd);
    throw CameraError(state_->device + " (" + state_->card +
                      "): not a single-planar video capture device with streaming I/O");
  }
}

V4l2Camera::~V4l2Camera() {
  if (state_->streaming) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    retryIoctl(state_->fd, VIDIOC_STREAMOFF, &type);
  }
  state_->releaseBuffers();
  ::close(state_->fd);
}

std::string V4l2Camera::id() const { return state_->device + " (" + state_->card + ")"; }

void V4l2Camera::start() {
  if (!state_->configured) throw std::logic_error("V4l2Camera::start before configure");
  if (state_->streaming) return;
  v4l2_requestbuffers request{};
  request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  request.memory = V4L2_MEMORY_MMAP;
  request.count = static_cast<std::uint32_t>(state_->config.bufferCount);
  if (retryIoctl(state_->fd, VIDIOC_REQBUFS, &request) != 0)
    state_->fail("cannot allocate buffers", errno);
  if (request.count < 2)
    throw CameraError(state_->device + ": the driver gave " + std::to_string(request.count) +
                      " buffer(s); streaming needs at least 2");
  state_->grantedBuffers = request.count;
  for (std::uint32_t index = 0; index < request.count; ++index) {
    v4l2_buffer buffer{};
    buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buffer.memory = V4L2_MEMORY_MMAP;
    buffer.index = index;
    if (retryIoctl(state_->fd, VIDIOC_QUERYBUF, &buffer) != 0) {
      const int error = errno;
      state_->releaseBuffers();
      state_->fail("cannot query buffer " + std::to_string(index), error);
    }
    MappedBuffer mapped;
    mapped.length = buffer.length;
    mapped.start = ::mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, state_->fd,
                          buffer.m.offset);
    if (mapped.start == MAP_FAILED) {
      const int error = errno;
      state_->releaseBuffers();
      state_->fail("cannot map buffer " + std::to_string(index), error);
    }
    state_->buffers.push_back(mapped);
    if (retryIoctl(state_->fd, VIDIOC_QBUF, &buffer) != 0) {
      const int error = errno;
      state_->releaseBuffers();
      state_->fail("cannot queue buffer " + std::to_string(index), error);
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (retryIoctl(state_->fd, VIDIOC_STREAMON, &type) != 0) {
    const int error = errno;
    state_->releaseBuffers();
    state_->fail("cannot start streaming", error);
  }
  state_->streaming = true;
  state_->firstSequence.reset();
  state_->dequeued = 0;
  state_->lockReachesFrame = 0;
  state_->locks = 0;
  state_->controlsBeforeLocks.clear();
}

void V4l2Camera::stop() {
  if (!state_->streaming) return;
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  retryIoctl(state_->fd, VIDIOC_STREAMOFF, &type);
  state_->streaming = false;
  state_->releaseBuffers();
  if (state_->locks > 0) {
    for (const auto& [id, value] : state_->controlsBeforeLocks)
      state_->setControl(id, value);
    state_->config.exposureUs = state_->exposureUsBeforeLocks;
    state_->config.gain = state_->gainBeforeLocks;
    state_->locks = 0;
  }
}

std::optional<int> V4l2Camera::readyDescriptor() const { return state_->fd; }

CaptureResult V4l2Camera::nextFrame(std::chrono::milliseconds timeout) {
  if (!state_->streaming) throw std::logic_error("V4l2Camera::nextFrame before start");
  pollfd ready{state_->fd, POLLIN, 0};
  const int polled = ::poll(&ready, 1, static_cast<int>(timeout.count()));
  if (polled == 0) return {CaptureResult::Status::Timeout, std::nullopt, ""};
  if (polled < 0 && errno != EINTR)
    return {CaptureResult::Status::Error, std::nullopt,
            state_->device + ": poll: " + std::strerror(errno)};
  v4l2_buffer buffer{};
  buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buffer.memory = V4L2_MEMORY_MMAP;
  if (retryIoctl(state_->fd, VIDIOC_DQBUF, &buffer) != 0) {
    if (errno == EAGAIN) return {CaptureResult::Status::Timeout, std::nullopt, ""};
    return {CaptureResult::Status::Error, std::nullopt,
            state_->device + ": cannot dequeue a frame: " + std::strerror(errno)};
  }
  // The buffer goes back to the driver whatever happens to its contents below.
  struct Requeue {
    int fd;
    v4l2_buffer& buffer;
    ~Requeue() { retryIoctl(fd, VIDIOC_QBUF, &buffer); }
  } requeue{state_->fd, buffer};
  const bool exposedBeforeLock = state_->dequeued++ < state_->lockReachesFrame;
  return state_->frameOf(buffer, exposedBeforeLock);
}

}  // namespace slicecap::hal
