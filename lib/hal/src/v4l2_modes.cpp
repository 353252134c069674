// A V4L2 device's formats and frame sizes, for the hardware check.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/v4l2_camera.hpp"

namespace slicecap::hal {
namespace {

int ioctlRetrying(int fd, unsigned long request, void* argument) {
  int result;
  do result = ::ioctl(fd, request, argument);
  while (result == -1 && errno == EINTR);
  return result;
}

std::string fourccName(std::uint32_t fourcc) {
  if (const std::optional<BayerFormat> bayer = bayerFormatFromV4l2(fourcc)) return bayerFormatName(*bayer);
  std::string text(4, ' ');
  for (int i = 0; i < 4; ++i) text[i] = static_cast<char>((fourcc >> (8 * i)) & 0xff);
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Discrete sizes only: a stepwise range (some UVC and bridge drivers) is said as a range.
std::vector<std::pair<int, int>> frameSizes(int fd, std::uint32_t fourcc) {
  std::vector<std::pair<int, int>> sizes;
  v4l2_frmsizeenum size{};
  size.pixel_format = fourcc;
  while (ioctlRetrying(fd, VIDIOC_ENUM_FRAMESIZES, &size) == 0 &&
         size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
    sizes.emplace_back(int(size.discrete.width), int(size.discrete.height));
    ++size.index;
  }
  return sizes;
}

}  // namespace

CameraModes listV4l2Modes(const std::string& devicePath) {
  const int fd = ::open(devicePath.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw CameraError(devicePath + ": cannot open: " + std::strerror(errno));
  v4l2_capability capability{};
  if (ioctlRetrying(fd, VIDIOC_QUERYCAP, &capability) != 0) {
    const int error = errno;
    ::close(fd);
    throw CameraError(devicePath + ": not a V4L2 device: " + std::strerror(error));
  }
  const std::uint32_t caps = (capability.capabilities & V4L2_CAP_DEVICE_CAPS) ? capability.device_caps
                                                                               : capability.capabilities;
  CameraModes modes;
  modes.id = "v4l2: " + devicePath + " (" + reinterpret_cast<const char*>(capability.card) + ")";
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) {
    ::close(fd);
    throw CameraError(modes.id + ": not a video capture device (a metadata or output node)");
  }
  v4l2_fmtdesc description{};
  description.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  while (ioctlRetrying(fd, VIDIOC_ENUM_FMT, &description) == 0) {
    OfferedFormat format = offeredFormat(fourccName(description.pixelformat),
                                         frameSizes(fd, description.pixelformat));
    // A Bayer fourcc decodeBayer does not read (8-bit, 14-bit) is RAW all the same.
    if (!format.raw && (description.flags & V4L2_FMT_FLAG_COMPRESSED) == 0 &&
        std::string(reinterpret_cast<const char*>(description.description)).find("Bayer") != std::string::npos)
      format.raw = true;
    modes.formats.push_back(std::move(format));
    ++description.index;
  }
  ::close(fd);
  return modes;
}

}  // namespace slicecap::hal
