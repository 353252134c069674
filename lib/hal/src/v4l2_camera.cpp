// V4L2 capture: format negotiation, manual controls, mmap buffers, poll-driven dequeue.
#include "slicecap/hal/v4l2_camera.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/raw_frame.hpp"
#include "slicecap/hal/v4l2_timestamp.hpp"

namespace slicecap::hal {
namespace {

int retryIoctl(int fd, unsigned long request, void* argument) {
  int result = 0;
  do {
    result = ::ioctl(fd, request, argument);
  } while (result == -1 && errno == EINTR);
  return result;
}

struct FormatChoice {
  std::uint32_t fourcc;
  RawLayout layout;
  std::optional<BayerFormat> bayer{};  ///< set for a RAW Bayer format (decodeBayer)
};

/// The RAW Bayer formats decodeBayer reads: 10- and 12-bit, CSI-2 packed first (a bridge such as
/// the Pi's unicam offers the sensor's own packing), then 16-bit words.
std::vector<FormatChoice> bayerFormats() {
  std::vector<FormatChoice> formats;
  for (std::uint32_t fourcc :
       {V4L2_PIX_FMT_SRGGB10P, V4L2_PIX_FMT_SGRBG10P, V4L2_PIX_FMT_SGBRG10P, V4L2_PIX_FMT_SBGGR10P,
        V4L2_PIX_FMT_SRGGB12P, V4L2_PIX_FMT_SGRBG12P, V4L2_PIX_FMT_SGBRG12P, V4L2_PIX_FMT_SBGGR12P,
        V4L2_PIX_FMT_SRGGB10, V4L2_PIX_FMT_SGRBG10, V4L2_PIX_FMT_SGBRG10, V4L2_PIX_FMT_SBGGR10,
        V4L2_PIX_FMT_SRGGB12, V4L2_PIX_FMT_SGRBG12, V4L2_PIX_FMT_SGBRG12, V4L2_PIX_FMT_SBGGR12,
        V4L2_PIX_FMT_SRGGB16, V4L2_PIX_FMT_SGRBG16, V4L2_PIX_FMT_SGBRG16, V4L2_PIX_FMT_SBGGR16})
    formats.push_back({fourcc, RawLayout::Y16, bayerFormatFromV4l2(fourcc)});
  return formats;
}

/// The formats slicecap takes, best first for each encoding: RAW Bayer first unless `raw` is
/// Off (only RAW when On). Compressed formats are left out on purpose: JPEG's quantisation would
/// be part of every measured value.
std::vector<FormatChoice> preferredFormats(PixelEncoding encoding, RawCapture raw) {
  if (raw == RawCapture::On) return bayerFormats();
  std::vector<FormatChoice> formats = {{V4L2_PIX_FMT_YUYV, RawLayout::Yuyv},
                                       {V4L2_PIX_FMT_RGB24, RawLayout::Rgb24},
                                       {V4L2_PIX_FMT_BGR24, RawLayout::Bgr24},
                                       {V4L2_PIX_FMT_YUV420, RawLayout::Yuv420},
                                       {V4L2_PIX_FMT_GREY, RawLayout::Grey8}};
  const FormatChoice y16{V4L2_PIX_FMT_Y16, RawLayout::Y16};
  if (encoding == PixelEncoding::Linear16)
    formats.insert(formats.begin(), y16);
  else
    formats.push_back(y16);
  if (raw == RawCapture::Auto) {
    std::vector<FormatChoice> withRaw = bayerFormats();
    withRaw.insert(withRaw.end(), formats.begin(), formats.end());
    return withRaw;
  }
  return formats;
}

std::string fourccText(std::uint32_t fourcc) {
  std::string text(4, ' ');
  for (int i = 0; i < 4; ++i) text[i] = static_cast<char>((fourcc >> (8 * i)) & 0xff);
  return text;
}

struct MappedBuffer {
  void* start = MAP_FAILED;
  std::size_t length = 0;
};

}  // namespace

struct V4l2Camera::State {
  std::string device;
  std::string card;
  int fd = -1;
  bool configured = false;
  bool streaming = false;
  CameraConfig config;
  RawLayout layout = RawLayout::Yuyv;
  std::optional<BayerFormat> bayer;  // RAW: the mosaic is twice the frame's size
  std::size_t strideBytes = 0;
  std::size_t imageBytes = 0;
  std::vector<MappedBuffer> buffers;
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

  std::optional<v4l2_queryctrl> queryControl(std::uint32_t id) const {
    v4l2_queryctrl query{};
    query.id = id;
    if (retryIoctl(fd, VIDIOC_QUERYCTRL, &query) != 0) return std::nullopt;
    if ((query.flags & V4L2_CTRL_FLAG_DISABLED) != 0) return std::nullopt;
    return query;
  }

  std::optional<std::int32_t> getControl(std::uint32_t id) const {
    v4l2_control control{};
    control.id = id;
    if (retryIoctl(fd, VIDIOC_G_CTRL, &control) != 0) return std::nullopt;
    return control.value;
  }

  /// The exposure and gain controls as they are, to put back: the modes first, then a value only
  /// where its mode leaves it to the user (an auto mode owns its value; shutter priority keeps
  /// the exposure time manual).
  std::vector<std::pair<std::uint32_t, std::int32_t>> exposureControls() const {
    const std::optional<std::int32_t> autoExposure = getControl(V4L2_CID_EXPOSURE_AUTO);
    const std::optional<std::int32_t> autoGain = getControl(V4L2_CID_AUTOGAIN);
    std::vector<std::pair<std::uint32_t, std::int32_t>> controls;
    if (autoExposure) controls.emplace_back(V4L2_CID_EXPOSURE_AUTO, *autoExposure);
    if (autoGain) controls.emplace_back(V4L2_CID_AUTOGAIN, *autoGain);
    const std::int32_t exposureMode = autoExposure.value_or(V4L2_EXPOSURE_MANUAL);
    if (exposureMode == V4L2_EXPOSURE_MANUAL || exposureMode == V4L2_EXPOSURE_SHUTTER_PRIORITY)
      if (const std::optional<std::int32_t> v = getControl(V4L2_CID_EXPOSURE_ABSOLUTE))
        controls.emplace_back(V4L2_CID_EXPOSURE_ABSOLUTE, *v);
    if (autoGain.value_or(0) == 0)
      if (const std::optional<std::int32_t> v = getControl(V4L2_CID_GAIN))
        controls.emplace_back(V4L2_CID_GAIN, *v);
    return controls;
  }

  bool setControl(std::uint32_t id, std::int32_t value) const {
    v4l2_control control{};
    control.id = id;
    control.value = value;
    return retryIoctl(fd, VIDIOC_S_CTRL, &control) == 0;
  }

  /// Sets a control to `wanted` clamped and stepped to its range; returns the value set, or
  /// nullopt when the device lacks the control or refuses it.
  std::optional<std::int32_t> setRangedControl(std::uint32_t id, double wanted) const {
    const std::optional<v4l2_queryctrl> query = queryControl(id);
    if (!query) return std::nullopt;
    const double step = query->step > 0 ? query->step : 1;
    double value = std::round((wanted - query->minimum) / step) * step + query->minimum;
    value = std::min<double>(std::max<double>(value, query->minimum), query->maximum);
    const auto set = static_cast<std::int32_t>(value);
    if (!setControl(id, set)) return std::nullopt;
    return set;
  }

  /// Auto exposure off and the exposure set, clamped to the control's range; returns the
  /// exposure set in microseconds (V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us), or nullopt when the
  /// device has no manual exposure.
  std::optional<double> setManualExposureUs(double wantedUs) const {
    setControl(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL);
    const std::optional<std::int32_t> set =
        setRangedControl(V4L2_CID_EXPOSURE_ABSOLUTE, wantedUs / 100.0);
    if (!set) return std::nullopt;
    return *set * 100.0;
  }

  /// Auto gain off and the gain set (the device's own units), clamped to its range; returns the
  /// gain set, or nullopt when the device lacks the control or refuses it.
  std::optional<std::int32_t> setManualGain(double wanted) const {
    setControl(V4L2_CID_AUTOGAIN, 0);
    return setRangedControl(V4L2_CID_GAIN, wanted);
  }

  void releaseBuffers() {
    for (MappedBuffer& buffer : buffers)
      if (buffer.start != MAP_FAILED) ::munmap(buffer.start, buffer.length);
    buffers.clear();
    v4l2_requestbuffers request{};
    request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    request.memory = V4L2_MEMORY_MMAP;
    request.count = 0;
    retryIoctl(fd, VIDIOC_REQBUFS, &request);
  }
};

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

ConfigResult V4l2Camera::configure(CameraConfig& config) {
  if (state_->streaming) throw std::logic_error("V4l2Camera::configure while streaming");
  std::vector<std::uint32_t> offered;
  v4l2_fmtdesc description{};
  description.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  while (retryIoctl(state_->fd, VIDIOC_ENUM_FMT, &description) == 0) {
    offered.push_back(description.pixelformat);
    ++description.index;
  }
  std::optional<FormatChoice> chosen;
  for (const FormatChoice& candidate : preferredFormats(config.encoding, config.raw)) {
    if (std::find(offered.begin(), offered.end(), candidate.fourcc) != offered.end()) {
      chosen = candidate;
      break;
    }
  }
  if (!chosen) {
    std::string list;
    for (std::uint32_t fourcc : offered) list += (list.empty() ? "" : ", ") + fourccText(fourcc);
    return {ConfigResult::Status::Invalid,
            std::string(config.raw == RawCapture::On
                            ? "camera_raw = on, but no RAW Bayer format slicecap decodes"
                            : "no uncompressed format slicecap can read") +
                " (the camera offers: " + (list.empty() ? std::string("none") : list) + ")"};
  }

  std::vector<std::string> adjustments;
  v4l2_format format{};
  format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  // A RAW mosaic is binned 2 x 2: the sensor mode twice the size asked for.
  const int scale = chosen->bayer ? 2 : 1;
  format.fmt.pix.width = static_cast<std::uint32_t>(scale * config.widthPx);
  format.fmt.pix.height = static_cast<std::uint32_t>(scale * config.heightPx);
  format.fmt.pix.pixelformat = chosen->fourcc;
  format.fmt.pix.field = V4L2_FIELD_NONE;
  if (retryIoctl(state_->fd, VIDIOC_S_FMT, &format) != 0) state_->fail("cannot set the format", errno);
  if (format.fmt.pix.pixelformat != chosen->fourcc)
    return {ConfigResult::Status::Invalid,
            "the driver replaced " + fourccText(chosen->fourcc) + " by " +
                fourccText(format.fmt.pix.pixelformat)};
  const int deliveredWidth = int(format.fmt.pix.width) / scale;
  const int deliveredHeight = int(format.fmt.pix.height) / scale;
  if (deliveredWidth != config.widthPx || deliveredHeight != config.heightPx) {
    adjustments.push_back("size " + std::to_string(config.widthPx) + "x" +
                          std::to_string(config.heightPx) + " -> " +
                          std::to_string(deliveredWidth) + "x" + std::to_string(deliveredHeight) +
                          (chosen->bayer ? " (RAW " + std::to_string(format.fmt.pix.width) + "x" +
                                               std::to_string(format.fmt.pix.height) +
                                               " binned 2 x 2)"
                                         : std::string()));
    config.widthPx = deliveredWidth;
    config.heightPx = deliveredHeight;
  }
  if (encodingOf(chosen->layout) != config.encoding) {
    adjustments.push_back(std::string("encoding ") + std::string(toString(config.encoding)) +
                          " -> " + std::string(toString(encodingOf(chosen->layout))));
    config.encoding = encodingOf(chosen->layout);
  }
  config.rawFormat.clear();
  if (chosen->bayer) {
    // V4L2 has no standard control for the sensor's black level.
    config.rawFormat = bayerFormatName(*chosen->bayer);
    adjustments.push_back("RAW " + config.rawFormat + " (" + fourccText(chosen->fourcc) +
                          "): the driver reports no black level; assumed " +
                          std::to_string(int(kDefaultBlackLevel16)) +
                          " of 65535 (64 at 10 bits, Raspberry Pi sensors' default)");
  }
  state_->layout = chosen->layout;
  state_->bayer = chosen->bayer;
  state_->strideBytes = format.fmt.pix.bytesperline != 0
                            ? format.fmt.pix.bytesperline
                        : chosen->bayer
                            ? minimalBayerStrideBytes(*chosen->bayer, int(format.fmt.pix.width))
                            : minimalStrideBytes(chosen->layout, config.widthPx, 0);
  state_->imageBytes = format.fmt.pix.sizeimage;

  // Locked white balance and gain control, then exposure: a sweep's frames must be comparable.
  state_->setControl(V4L2_CID_AUTO_WHITE_BALANCE, 0);
  if (config.exposureUs) {
    const std::optional<double> setUs = state_->setManualExposureUs(*config.exposureUs);
    if (!setUs) {
      adjustments.push_back("no manual exposure: left to the camera");
      config.exposureUs.reset();
    } else if (std::abs(*setUs - *config.exposureUs) > 1e-6) {
      adjustments.push_back("exposure " + std::to_string(*config.exposureUs) + " us -> " +
                            std::to_string(*setUs) + " us");
      config.exposureUs = *setUs;
    }
  }
  if (config.gain) {
    const std::optional<std::int32_t> set = state_->setManualGain(*config.gain);
    if (!set) {
      adjustments.push_back("no manual gain: left to the camera");
      config.gain.reset();
    } else if (*set != *config.gain) {
      adjustments.push_back("gain " + std::to_string(*config.gain) + " -> " + std::to_string(*set));
      config.gain = *set;
    }
  }
  config.bufferCount = std::max(config.bufferCount, 2);
  state_->config = config;
  state_->configured = true;
  return ConfigResult::fromAdjustments(adjustments);
}

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
  if ((buffer.flags & V4L2_BUF_FLAG_ERROR) != 0)
    return {CaptureResult::Status::Error, std::nullopt,
            state_->device + ": the driver marked frame " + std::to_string(buffer.sequence) +
                " as corrupted"};
  const MappedBuffer& mapped = state_->buffers.at(buffer.index);
  RawFrameView raw;
  raw.layout = state_->layout;
  raw.widthPx = state_->config.widthPx;
  raw.heightPx = state_->config.heightPx;
  const std::size_t used = buffer.bytesused != 0 ? buffer.bytesused : mapped.length;
  const auto* bytes = static_cast<const std::uint8_t*>(mapped.start);
  if (raw.layout == RawLayout::Yuv420) {
    const std::size_t lumaBytes = state_->strideBytes * std::size_t(raw.heightPx);
    const std::size_t chromaStride = state_->strideBytes / 2;
    const std::size_t chromaBytes = chromaStride * std::size_t((raw.heightPx + 1) / 2);
    if (used < lumaBytes + 2 * chromaBytes)
      return {CaptureResult::Status::Error, std::nullopt,
              state_->device + ": frame " + std::to_string(buffer.sequence) + " is truncated"};
    raw.planes[0] = {bytes, lumaBytes};
    raw.planes[1] = {bytes + lumaBytes, chromaBytes};
    raw.planes[2] = {bytes + lumaBytes + chromaBytes, chromaBytes};
    raw.strideBytes[0] = state_->strideBytes;
    raw.strideBytes[1] = raw.strideBytes[2] = chromaStride;
  } else {
    raw.planes[0] = {bytes, std::min(used, mapped.length)};
    raw.strideBytes[0] = state_->strideBytes;
  }
  Frame frame;
  try {
    if (state_->bayer) {
      BayerFrameView mosaic;
      mosaic.format = *state_->bayer;
      mosaic.widthPx = 2 * raw.widthPx;
      mosaic.heightPx = 2 * raw.heightPx;
      mosaic.bytes = raw.planes[0];
      mosaic.strideBytes = state_->strideBytes;
      frame.image = decodeBayer(mosaic, BayerBlackLevels::uniform(kDefaultBlackLevel16));
    } else {
      frame.image = toImage(raw);
    }
  } catch (const RawFrameError& error) {
    return {CaptureResult::Status::Error, std::nullopt,
            state_->device + ": frame " + std::to_string(buffer.sequence) + ": " + error.what()};
  }
  if (!state_->firstSequence) state_->firstSequence = buffer.sequence;
  frame.encoding = state_->bayer ? PixelEncoding::Linear16 : encodingOf(raw.layout);
  frame.metadata.sequence = buffer.sequence - *state_->firstSequence;
  frame.metadata.timestampUs =
      std::int64_t(buffer.timestamp.tv_sec) * 1'000'000 + buffer.timestamp.tv_usec;
  frame.metadata.exposureUs = exposedBeforeLock ? state_->exposureBeforeLockUs
                                                : state_->config.exposureUs.value_or(0.0);
  frame.metadata.gain =
      exposedBeforeLock ? state_->gainBeforeLock : state_->config.gain.value_or(1.0);
  frame.metadata.exposureLocks = exposedBeforeLock ? state_->locks - 1 : state_->locks;
  // What the timestamp marks is in the buffer's flags; an exposure left to the camera (0) is
  // unknown, so an end-of-frame timestamp then says nothing about the start.
  frame.metadata.exposureStartUs =
      v4l2ExposureStartUs(buffer.flags, frame.metadata.timestampUs, frame.metadata.exposureUs,
                          state_->config.readoutUs);
  return {CaptureResult::Status::Frame, std::move(frame), ""};
}

ExposureLock V4l2Camera::lockExposure(const ExposureSetting& wanted) {
  if (!state_->streaming) throw std::logic_error("V4l2Camera::lockExposure before start");
  // A lock the device refuses halfway (e.g. the gain after the exposure) is undone: a fixed
  // exposure that neither the frames nor the status report would be worse than none.
  const std::vector<std::pair<std::uint32_t, std::int32_t>> before = state_->exposureControls();
  auto refuse = [&](const std::string& reason) -> ExposureLock {
    for (const auto& [id, value] : before)
      state_->setControl(id, value);
    return {std::nullopt, reason};
  };
  const std::optional<double> exposureUs = state_->setManualExposureUs(wanted.exposureUs);
  if (!exposureUs) return refuse(state_->device + " has no manual exposure");
  // Auto gain off too, or it would undo the metering; a camera without a gain control is unity.
  double gain = 1.0;
  if (const std::optional<v4l2_queryctrl> query = state_->queryControl(V4L2_CID_GAIN)) {
    const std::optional<std::int32_t> set =
        state_->setManualGain(wanted.gain.value_or(query->default_value));
    if (!set) return refuse(state_->device + " refused a manual gain");
    gain = *set;
  } else {
    state_->setControl(V4L2_CID_AUTOGAIN, 0);
  }
  if (state_->locks == 0) {
    state_->controlsBeforeLocks = before;
    state_->exposureUsBeforeLocks = state_->config.exposureUs;
    state_->gainBeforeLocks = state_->config.gain;
  }
  ++state_->locks;
  state_->exposureBeforeLockUs = state_->config.exposureUs.value_or(0.0);
  state_->gainBeforeLock = state_->config.gain.value_or(1.0);
  state_->lockReachesFrame = state_->dequeued + state_->grantedBuffers + 1;
  state_->config.exposureUs = *exposureUs;
  state_->config.gain = gain;
  return {ExposureSetting{*exposureUs, gain}, ""};
}

}  // namespace slicecap::hal
