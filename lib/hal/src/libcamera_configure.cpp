// The libcamera camera's stream choice: the RAW stream where the camera offers one slicecap
// decodes (and camera_raw allows it), else the processed stream in a format slicecap reads.
#include <libcamera/color_space.h>

#include <algorithm>
#include <stdexcept>

#include "libcamera_compat.hpp"
#include "libcamera_state.hpp"

namespace slicecap::hal {

using namespace libcamera_parts;

RawValidator libcamera_parts::rawValidator(libcamera::CameraConfiguration& configuration,
                                           int bufferCount) {
  return [&configuration, bufferCount](const std::string& format, std::pair<int, int> modePx) {
    libcamera::StreamConfiguration& stream = configuration.at(0);
    const libcamera::PixelFormat pixelFormat = libcamera::PixelFormat::fromString(format);
    if (!pixelFormat.isValid()) return RawValidation{true, format, modePx};
    stream.pixelFormat = pixelFormat;
    stream.size = libcamera::Size(unsigned(modePx.first), unsigned(modePx.second));
    stream.bufferCount = static_cast<unsigned>(std::max(bufferCount, 2));
    // No flips: a transform would also change the CFA order of the samples.
    libcamera_compat::keepSensorOrientation(configuration);
    if (configuration.validate() == libcamera::CameraConfiguration::Invalid)
      return RawValidation{true, format, modePx};
    return RawValidation{false, stream.pixelFormat.toString(),
                         {int(stream.size.width), int(stream.size.height)}};
  };
}

libcamera_parts::RawAttempt LibcameraCamera::State::tryRaw(const CameraConfig& wanted) {
  RawAttempt attempt;
  auto generated = libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::Raw);
  if (!generated || generated->empty()) return attempt;
  const libcamera::StreamConfiguration& stream = generated->at(0);
  // A pipeline without RAW (uvcvideo) answers the Raw role with its processed formats: then
  // no RAW is offered and nothing is said.
  const std::vector<OfferedFormat> offered = offeredFormatsOf(stream);
  if (std::none_of(offered.begin(), offered.end(), [](const OfferedFormat& f) { return f.raw; }))
    return attempt;
  // Every request is validated and the format validation leaves is checked, on every Pi: a Pi 5
  // turns the packed format libcamera proposes into its lossy compressed one, and grants the
  // unpacked twin that negotiateRawStream asks for next (camera_modes.hpp).
  const RawStreamChoice choice =
      negotiateRawStream(offered, stream.pixelFormat.toString(), wanted.widthPx,
                         wanted.heightPx, rawValidator(*generated, wanted.bufferCount));
  if (choice.format.empty()) {
    attempt.reason = choice.reason;
    return attempt;
  }
  // The last validation was the granted request: `generated` holds it.
  attempt.format = bayerFormatFromLibcameraName(choice.format);
  attempt.notes = choice.notes;
  attempt.configuration = std::move(generated);
  return attempt;
}

std::optional<YuvEncoding> yuvEncodingOf(const libcamera::ColorSpace& colorSpace) {
  const YuvRange range =
      colorSpace.range == libcamera::ColorSpace::Range::Full ? YuvRange::Full : YuvRange::Limited;
  switch (colorSpace.ycbcrEncoding) {
    case libcamera::ColorSpace::YcbcrEncoding::Rec601:
      return YuvEncoding{YcbcrMatrix::Rec601, range};
    case libcamera::ColorSpace::YcbcrEncoding::Rec709:
      return YuvEncoding{YcbcrMatrix::Rec709, range};
    case libcamera::ColorSpace::YcbcrEncoding::Rec2020:
      return YuvEncoding{YcbcrMatrix::Rec2020, range};
    case libcamera::ColorSpace::YcbcrEncoding::None:
      break;
  }
  return std::nullopt;
}

namespace {

/// Why camera_raw = on cannot be met: the RAW attempt's `reason` without the fallback that `on`
/// refuses.
std::string rawRequiredReason(const std::string& cameraName, const std::string& reason) {
  std::string cause = reason.empty() ? std::string("it offers no RAW stream") : reason;
  if (const auto fallback = cause.find(": the processed stream is used instead");
      fallback != std::string::npos)
    cause.erase(fallback);
  return cameraName + ": camera_raw = on, but " + cause +
         " (camera_raw = auto takes the processed stream instead)";
}

/// The first of kFormats among `offered`; nullopt when none is.
std::optional<libcamera::PixelFormat> firstReadableFormat(
    const std::vector<libcamera::PixelFormat>& offered) {
  for (const FormatChoice& choice : kFormats)
    if (std::find(offered.begin(), offered.end(), choice.format) != offered.end())
      return choice.format;
  return std::nullopt;
}

/// Takes the size and buffers of the applied processed `stream` into `config`, and its
/// encoding, said in `adjustments` when it changes.
void adoptProcessedStream(const libcamera::StreamConfiguration& stream, CameraConfig& config,
                          std::vector<std::string>& adjustments) {
  config.widthPx = static_cast<int>(stream.size.width);
  config.heightPx = static_cast<int>(stream.size.height);
  config.bufferCount = static_cast<int>(stream.bufferCount);
  if (config.encoding != PixelEncoding::Srgb8) {
    adjustments.push_back("encoding linear16 -> srgb8 (processed streams are 8-bit)");
    config.encoding = PixelEncoding::Srgb8;
  }
}

/// `result` with `notes` added to what was adjusted (an Invalid result stays as it is).
ConfigResult withNotes(ConfigResult result, const std::vector<std::string>& notes) {
  if (result.status == ConfigResult::Status::Invalid || notes.empty()) return result;
  std::vector<std::string> all;
  if (!result.reason.empty()) all.push_back(result.reason);
  all.insert(all.end(), notes.begin(), notes.end());
  return ConfigResult::fromAdjustments(all);
}

}  // namespace

std::vector<std::string> LibcameraCamera::State::pinFrameDuration(CameraConfig& cameraConfig) {
  frameDurationLimitsUs.reset();
  std::optional<FrameDurationRange> listed;
  const libcamera::ControlInfoMap& offered = camera->controls();
  if (const auto info = offered.find(&libcamera::controls::FrameDurationLimits);
      info != offered.end() &&
      info->second.min().type() == libcamera::ControlTypeInteger64 &&
      info->second.max().type() == libcamera::ControlTypeInteger64)
    listed = FrameDurationRange{info->second.min().get<std::int64_t>(),
                                info->second.max().get<std::int64_t>()};
  FrameDurationPlan plan = planFrameDuration(cameraConfig.frameDurationUs, listed);
  frameDurationLimitsUs = plan.limitsUs;
  // What the frames will run at, as far as the camera says; a camera that cannot pin it runs
  // at its own duration, unknown here.
  if (cameraConfig.frameDurationUs) cameraConfig.frameDurationUs = plan.grantedUs;
  if (cameraConfig.exposureUs) {
    const ExposureInFrame inFrame =
        clampExposureToFrame(*cameraConfig.exposureUs, cameraConfig.frameDurationUs);
    cameraConfig.exposureUs = inFrame.exposureUs;
    if (inFrame.note) plan.notes.push_back(*inFrame.note);
  }
  for (const std::string& note : plan.notes) warnOnce(name() + ": " + note);
  config.frameDurationUs = cameraConfig.frameDurationUs;
  config.exposureUs = cameraConfig.exposureUs;
  return plan.notes;
}

ConfigResult LibcameraCamera::configure(CameraConfig& config) {
  ConfigResult result = configureStream(config);
  if (result.status == ConfigResult::Status::Invalid) return result;
  // After the stream is applied: the Pi's IPA lists the sensor mode's frame durations then.
  return withNotes(std::move(result), state_->pinFrameDuration(config));
}

ConfigResult LibcameraCamera::configureStream(CameraConfig& config) {
  if (state_->streaming) throw std::logic_error("LibcameraCamera::configure while streaming");
  config.rawFormat.clear();
  state_->bayer.reset();
  std::vector<std::string> adjustments;
  if (config.raw != RawCapture::Off) {
    RawAttempt raw = state_->tryRaw(config);
    if (raw.configuration) {
      // A pipeline that validates a RAW-only configuration may still refuse to apply it.
      const int result = state_->camera->configure(raw.configuration.get());
      if (result == 0) {
        // What validation changed (a Pi 5's packed RAW replaced): said once and in the result.
        for (const std::string& note : raw.notes) {
          warnOnce(state_->name() + ": RAW " + note);
          adjustments.push_back("RAW " + note);
        }
        return configureRaw(config, std::move(raw.configuration), *raw.format,
                            std::move(adjustments));
      }
      raw.reason = "libcamera could not apply the RAW stream " +
                   raw.configuration->at(0).toString() + " (" + std::strerror(-result) +
                   "): the processed stream is used instead";
    }
    if (config.raw == RawCapture::On)
      return {ConfigResult::Status::Invalid, rawRequiredReason(state_->name(), raw.reason)};
    if (!raw.reason.empty()) {
      // Said once on stderr and in every sweep's configuration result (the session's journal).
      warnOnce(state_->name() + ": " + raw.reason);
      adjustments.push_back(raw.reason);
    }
  }
  return state_->configureProcessed(config, std::move(adjustments));
}

ConfigResult LibcameraCamera::State::configureProcessed(CameraConfig& cameraConfig,
                                                        std::vector<std::string> adjustments) {
  configuration =
      libcamera_compat::generateConfiguration(*camera, libcamera::StreamRole::VideoRecording);
  if (!configuration || configuration->empty())
    return {ConfigResult::Status::Invalid, name() + " offers no video stream"};
  libcamera::StreamConfiguration& stream = configuration->at(0);
  const std::optional<libcamera::PixelFormat> chosen =
      firstReadableFormat(stream.formats().pixelformats());
  if (!chosen)
    return {ConfigResult::Status::Invalid,
            name() + " offers none of BGR888, RGB888, XRGB8888, YUYV, YUV420"};
  stream.pixelFormat = *chosen;
  stream.size = libcamera::Size(static_cast<unsigned>(cameraConfig.widthPx),
                                static_cast<unsigned>(cameraConfig.heightPx));
  stream.bufferCount = static_cast<unsigned>(std::max(cameraConfig.bufferCount, 2));
  libcamera_compat::keepSensorOrientation(*configuration);

  switch (configuration->validate()) {
    case libcamera::CameraConfiguration::Invalid:
      return {ConfigResult::Status::Invalid, name() + " cannot deliver " + stream.toString()};
    case libcamera::CameraConfiguration::Adjusted:
      adjustments.push_back("libcamera adjusted the stream to " + stream.toString());
      break;
    case libcamera::CameraConfiguration::Valid:
      break;
  }
  const std::optional<RawLayout> streamLayout = layoutOf(stream.pixelFormat);
  if (!streamLayout)
    return {ConfigResult::Status::Invalid,
            name() + " changed the format to " + stream.pixelFormat.toString() +
                ", which slicecap cannot read"};
  // A YUV stream is decoded by the colour space validation left in it; without one its matrix
  // and range are unknown, and a wrong guess is far off (Rec.709 read as BT.601: a saturated
  // red's R 233 of 255; full range read as limited: a grey at 200 as 214): refused, not guessed.
  std::optional<YuvEncoding> streamYuv;
  if (isYuv(*streamLayout)) {
    streamYuv = stream.colorSpace ? yuvEncodingOf(*stream.colorSpace) : std::nullopt;
    if (!streamYuv)
      return {ConfigResult::Status::Invalid,
              name() + " reports " +
                  (stream.colorSpace ? "the colour space " + stream.colorSpace->toString() +
                                           ", which has no YCbCr matrix,"
                                     : std::string("no colour space")) +
                  " for its " + stream.pixelFormat.toString() +
                  " stream: its YCbCr matrix and range are unknown, and slicecap does not guess "
                  "them (a camera that offers RGB, or RAW with camera_raw = auto, avoids it)"};
    warnOnce(name() + ": its " + stream.pixelFormat.toString() + " stream is decoded as " +
             toString(*streamYuv) + " (colour space " + stream.colorSpace->toString() + ")");
  }
  if (const int result = camera->configure(configuration.get()); result != 0)
    fail("cannot apply the configuration " + stream.toString(), result);

  adoptProcessedStream(stream, cameraConfig, adjustments);
  layout = *streamLayout;
  yuv = streamYuv;
  strideBytes = stream.stride;
  config = cameraConfig;
  configured = true;
  return ConfigResult::fromAdjustments(adjustments);
}

ConfigResult LibcameraCamera::configureRaw(
    CameraConfig& config, std::unique_ptr<libcamera::CameraConfiguration> configuration,
    const BayerFormat& format, std::vector<std::string> adjustments) {
  const libcamera::StreamConfiguration& stream = configuration->at(0);
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

}  // namespace slicecap::hal
