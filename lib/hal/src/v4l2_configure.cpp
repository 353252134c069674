// The V4L2 camera's format choice: RAW Bayer first unless camera_raw is off, else the
// uncompressed formats slicecap reads, the size the driver grants, and the locked controls.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "slicecap/hal/frame_timing.hpp"
#include "v4l2_state.hpp"

namespace slicecap::hal {

using namespace v4l2_parts;

namespace {

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
  // RGB before YUV: a YUV stream needs the driver's word on its matrix and range.
  std::vector<FormatChoice> formats = {{V4L2_PIX_FMT_RGB24, RawLayout::Rgb24},
                                       {V4L2_PIX_FMT_BGR24, RawLayout::Bgr24},
                                       {V4L2_PIX_FMT_YUYV, RawLayout::Yuyv},
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

/// The pixel formats the device lists, in its order.
std::vector<std::uint32_t> offeredFormats(int fd) {
  std::vector<std::uint32_t> offered;
  v4l2_fmtdesc description{};
  description.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  while (retryIoctl(fd, VIDIOC_ENUM_FMT, &description) == 0) {
    offered.push_back(description.pixelformat);
    ++description.index;
  }
  return offered;
}

/// The first of `preferred` the device offers; nullopt when it offers none of them.
std::optional<FormatChoice> firstOffered(const std::vector<FormatChoice>& preferred,
                                         const std::vector<std::uint32_t>& offered) {
  for (const FormatChoice& candidate : preferred)
    if (std::find(offered.begin(), offered.end(), candidate.fourcc) != offered.end())
      return candidate;
  return std::nullopt;
}

/// Why no offered format will do, naming what the camera offers.
std::string noUsableFormatReason(RawCapture raw, const std::vector<std::uint32_t>& offered) {
  std::string list;
  for (std::uint32_t fourcc : offered) list += (list.empty() ? "" : ", ") + fourccText(fourcc);
  return std::string(raw == RawCapture::On
                         ? "camera_raw = on, but no RAW Bayer format slicecap decodes"
                         : "no uncompressed format slicecap can read") +
         " (the camera offers: " + (list.empty() ? std::string("none") : list) + ")";
}

/// The VIDIOC_S_FMT request for `chosen` at the configured size.
v4l2_format requestedFormat(const FormatChoice& chosen, const CameraConfig& config) {
  v4l2_format format{};
  format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  // A RAW mosaic is binned 2 x 2: the sensor mode twice the size asked for.
  const int scale = chosen.bayer ? 2 : 1;
  format.fmt.pix.width = static_cast<std::uint32_t>(scale * config.widthPx);
  format.fmt.pix.height = static_cast<std::uint32_t>(scale * config.heightPx);
  format.fmt.pix.pixelformat = chosen.fourcc;
  format.fmt.pix.field = V4L2_FIELD_NONE;
  return format;
}

/// Takes the size and encoding the driver granted for `chosen` into `config`, each change said
/// in `adjustments`, and names the RAW format.
void adoptGrantedFormat(const FormatChoice& chosen, const v4l2_format& format,
                        CameraConfig& config, std::vector<std::string>& adjustments) {
  const int scale = chosen.bayer ? 2 : 1;
  const int deliveredWidth = int(format.fmt.pix.width) / scale;
  const int deliveredHeight = int(format.fmt.pix.height) / scale;
  if (deliveredWidth != config.widthPx || deliveredHeight != config.heightPx) {
    adjustments.push_back("size " + std::to_string(config.widthPx) + "x" +
                          std::to_string(config.heightPx) + " -> " +
                          std::to_string(deliveredWidth) + "x" + std::to_string(deliveredHeight) +
                          (chosen.bayer ? " (RAW " + std::to_string(format.fmt.pix.width) + "x" +
                                              std::to_string(format.fmt.pix.height) +
                                              " binned 2 x 2)"
                                        : std::string()));
    config.widthPx = deliveredWidth;
    config.heightPx = deliveredHeight;
  }
  if (encodingOf(chosen.layout) != config.encoding) {
    adjustments.push_back(std::string("encoding ") + std::string(toString(config.encoding)) +
                          " -> " + std::string(toString(encodingOf(chosen.layout))));
    config.encoding = encodingOf(chosen.layout);
  }
  config.rawFormat.clear();
  if (chosen.bayer) {
    // V4L2 has no standard control for the sensor's black level.
    config.rawFormat = bayerFormatName(*chosen.bayer);
    adjustments.push_back("RAW " + config.rawFormat + " (" + fourccText(chosen.fourcc) +
                          "): the driver reports no black level; assumed " +
                          std::to_string(int(kDefaultBlackLevel16)) +
                          " of 65535 (64 at 10 bits, Raspberry Pi sensors' default)");
  }
}

/// The bytes between rows: the driver's, else the least the format takes.
std::size_t strideBytesOf(const FormatChoice& chosen, const v4l2_format& format, int widthPx) {
  return format.fmt.pix.bytesperline != 0 ? format.fmt.pix.bytesperline
         : chosen.bayer ? minimalBayerStrideBytes(*chosen.bayer, int(format.fmt.pix.width))
                        : minimalStrideBytes(chosen.layout, widthPx, 0);
}

/// Takes the exposure the device set (`setUs`, nullopt: it has no manual exposure) into
/// `config`, the change said in `adjustments`.
void adoptSetExposure(std::optional<double> setUs, CameraConfig& config,
                      std::vector<std::string>& adjustments) {
  if (!setUs) {
    adjustments.push_back("no manual exposure: left to the camera");
    config.exposureUs.reset();
  } else if (std::abs(*setUs - *config.exposureUs) > 1e-6) {
    adjustments.push_back("exposure " + std::to_string(*config.exposureUs) + " us -> " +
                          std::to_string(*setUs) + " us");
    config.exposureUs = *setUs;
  }
}

/// Takes the gain the device set (`set`, nullopt: it has no manual gain) into `config`, the
/// change said in `adjustments`.
void adoptSetGain(std::optional<std::int32_t> set, CameraConfig& config,
                  std::vector<std::string>& adjustments) {
  if (!set) {
    adjustments.push_back("no manual gain: left to the camera");
    config.gain.reset();
  } else if (*set != *config.gain) {
    adjustments.push_back("gain " + std::to_string(*config.gain) + " -> " + std::to_string(*set));
    config.gain = *set;
  }
}

/// The pinned frame duration as the device's frame interval (VIDIOC_S_PARM timeperframe, where
/// it lists V4L2_CAP_TIMEPERFRAME), read back: `config.frameDurationUs` becomes what the driver
/// granted, or nullopt where it cannot set one. Returns what changed; `granted` says what it runs.
std::vector<std::string> pinFrameInterval(int fd, const std::string& device, CameraConfig& config,
                                          std::string& granted) {
  if (!config.frameDurationUs) return {};
  const double wantedUs = *config.frameDurationUs;
  const auto us = [](double value) { return std::to_string(std::llround(value)) + " us"; };
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (retryIoctl(fd, VIDIOC_G_PARM, &parm) != 0 ||
      (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) == 0) {
    config.frameDurationUs.reset();
    return {"frame duration " + us(wantedUs) + " not pinned: " + device +
            " sets no frame interval (V4L2_CAP_TIMEPERFRAME)"};
  }
  const TimePerFrame wanted = timePerFrameOf(wantedUs);
  parm.parm.capture.timeperframe.numerator = wanted.numerator;
  parm.parm.capture.timeperframe.denominator = wanted.denominator;
  if (retryIoctl(fd, VIDIOC_S_PARM, &parm) != 0) {
    config.frameDurationUs.reset();
    return {"frame duration " + us(wantedUs) + " not pinned: " + device +
            " refused the frame interval (" + std::strerror(errno) + ")"};
  }
  // S_PARM writes back the interval the driver chose (a UVC camera: its nearest listed one).
  const std::optional<double> grantedUs = frameDurationUsOf(
      {parm.parm.capture.timeperframe.numerator, parm.parm.capture.timeperframe.denominator});
  config.frameDurationUs = grantedUs;
  granted = "frame interval " + std::to_string(parm.parm.capture.timeperframe.numerator) + "/" +
            std::to_string(parm.parm.capture.timeperframe.denominator) + " s";
  if (grantedUs && std::abs(*grantedUs - wantedUs) <= 1.0) return {};
  return {"frame duration " + us(wantedUs) + " -> " +
          (grantedUs ? us(*grantedUs) : std::string("unknown")) + " (" +
          device + "'s nearest frame interval)"};
}

}  // namespace

std::optional<YuvEncoding> yuvEncodingOfV4l2(std::uint32_t colorspace, std::uint32_t ycbcrEncoding,
                                             std::uint32_t quantization, std::string* why) {
  const auto fail = [why](std::string text) {
    if (why) *why = std::move(text);
    return std::nullopt;
  };
  if (colorspace == V4L2_COLORSPACE_DEFAULT)
    return fail("the driver reports no colorspace (V4L2_COLORSPACE_DEFAULT)");
  if (ycbcrEncoding == V4L2_YCBCR_ENC_DEFAULT)
    ycbcrEncoding = V4L2_MAP_YCBCR_ENC_DEFAULT(colorspace);
  if (quantization == V4L2_QUANTIZATION_DEFAULT)
    quantization = V4L2_MAP_QUANTIZATION_DEFAULT(false, colorspace, ycbcrEncoding);
  YuvEncoding encoding;
  switch (ycbcrEncoding) {
    case V4L2_YCBCR_ENC_601:
    case V4L2_YCBCR_ENC_XV601:
      encoding.matrix = YcbcrMatrix::Rec601;
      break;
    case V4L2_YCBCR_ENC_709:
    case V4L2_YCBCR_ENC_XV709:
      encoding.matrix = YcbcrMatrix::Rec709;
      break;
    case V4L2_YCBCR_ENC_BT2020:
      encoding.matrix = YcbcrMatrix::Rec2020;
      break;
    default:
      return fail("its Y'CbCr encoding " + std::to_string(ycbcrEncoding) +
                  " (v4l2_ycbcr_encoding) is not one slicecap decodes");
  }
  encoding.range = quantization == V4L2_QUANTIZATION_FULL_RANGE ? YuvRange::Full : YuvRange::Limited;
  return encoding;
}

ConfigResult V4l2Camera::configure(CameraConfig& config) {
  if (state_->streaming) throw std::logic_error("V4l2Camera::configure while streaming");
  const std::vector<std::uint32_t> offered = offeredFormats(state_->fd);
  const std::optional<FormatChoice> chosen =
      firstOffered(preferredFormats(config.encoding, config.raw), offered);
  if (!chosen) return {ConfigResult::Status::Invalid, noUsableFormatReason(config.raw, offered)};

  std::vector<std::string> adjustments;
  v4l2_format format = requestedFormat(*chosen, config);
  if (retryIoctl(state_->fd, VIDIOC_S_FMT, &format) != 0) state_->fail("cannot set the format", errno);
  if (format.fmt.pix.pixelformat != chosen->fourcc)
    return {ConfigResult::Status::Invalid,
            "the driver replaced " + fourccText(chosen->fourcc) + " by " +
                fourccText(format.fmt.pix.pixelformat)};
  // A YUV stream is decoded by the colour space the driver reports, never by a guess.
  std::optional<YuvEncoding> yuv;
  if (isYuv(chosen->layout)) {
    std::string why;
    // The extended fields (ycbcr_enc, quantization) count only where the kernel marks them.
    const bool extended = format.fmt.pix.priv == V4L2_PIX_FMT_PRIV_MAGIC;
    yuv = yuvEncodingOfV4l2(format.fmt.pix.colorspace, extended ? format.fmt.pix.ycbcr_enc : 0,
                            extended ? format.fmt.pix.quantization : 0, &why);
    if (!yuv)
      return {ConfigResult::Status::Invalid,
              state_->device + ": " + fourccText(chosen->fourcc) + ": " + why +
                  ": its YCbCr matrix and range are unknown, and slicecap does not guess them"};
  }
  adoptGrantedFormat(*chosen, format, config, adjustments);
  state_->layout = chosen->layout;
  state_->yuv = yuv;
  state_->bayer = chosen->bayer;
  state_->strideBytes = strideBytesOf(*chosen, format, config.widthPx);
  state_->imageBytes = format.fmt.pix.sizeimage;

  // The frame interval first: the exposure is held inside it.
  std::string timing;
  for (std::string& note : pinFrameInterval(state_->fd, state_->device, config, timing))
    adjustments.push_back(std::move(note));
  if (config.mainsHz) state_->setPowerLineFrequency(*config.mainsHz, timing);
  if (!timing.empty()) std::cerr << "slicecap: " << state_->device << ": " << timing << " (read back)\n";
  // Locked white balance and gain control, then exposure: a sweep's frames must be comparable.
  state_->setControl(V4L2_CID_AUTO_WHITE_BALANCE, 0);
  if (config.exposureUs) {
    const ExposureInFrame inFrame = clampExposureToFrame(*config.exposureUs, config.frameDurationUs);
    if (inFrame.note) adjustments.push_back(*inFrame.note);
    config.exposureUs = inFrame.exposureUs;
    adoptSetExposure(state_->setManualExposureUs(*config.exposureUs), config, adjustments);
  }
  if (config.gain) adoptSetGain(state_->setManualGain(*config.gain), config, adjustments);
  config.bufferCount = std::max(config.bufferCount, 2);
  state_->config = config;
  state_->configured = true;
  return ConfigResult::fromAdjustments(adjustments);
}

}  // namespace slicecap::hal
