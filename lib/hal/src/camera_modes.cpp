// The RAW stream choice and the listing of a camera's formats and modes.
#include "slicecap/hal/camera_modes.hpp"

#include <algorithm>

#include "slicecap/hal/bayer_frame.hpp"

namespace slicecap::hal {

OfferedFormat offeredFormat(std::string name, std::vector<std::pair<int, int>> sizesPx) {
  OfferedFormat format;
  format.raw = isRawFormatName(name);
  format.decodable = format.raw && bayerFormatFromLibcameraName(name).has_value();
  format.name = std::move(name);
  format.sizesPx = std::move(sizesPx);
  return format;
}

RawStreamChoice chooseRawStream(const std::vector<OfferedFormat>& offered,
                                std::string_view proposedFormat, int wantedWidthPx,
                                int wantedHeightPx) {
  RawStreamChoice choice;
  std::vector<const OfferedFormat*> raw;
  for (const OfferedFormat& format : offered)
    if (format.raw) raw.push_back(&format);
  if (raw.empty()) {
    choice.reason = "the camera offers no RAW stream";
    return choice;
  }
  // The sensor's own packing, which libcamera proposes, avoids a conversion in the pipeline.
  const OfferedFormat* chosen = nullptr;
  for (const OfferedFormat* format : raw)
    if (format->decodable && format->name == proposedFormat) chosen = format;
  for (const OfferedFormat* format : raw)
    if (!chosen && format->decodable) chosen = format;
  if (!chosen) {
    const auto proposed = std::find_if(raw.begin(), raw.end(), [&](const OfferedFormat* format) {
      return format->name == proposedFormat;
    });
    choice.reason = undecodableRawReason((proposed != raw.end() ? *proposed : raw.front())->name);
    return choice;
  }
  choice.format = chosen->name;
  choice.modePx = chooseBayerSize(chosen->sizesPx, wantedWidthPx, wantedHeightPx)
                      .value_or(std::pair{2 * wantedWidthPx, 2 * wantedHeightPx});
  choice.deliveredPx = {choice.modePx.first / 2, choice.modePx.second / 2};
  return choice;
}

namespace {

/// One request negotiateRawStream may make: a format and the sizes its mode is chosen among.
struct RawRequest {
  std::string format;
  const std::vector<std::pair<int, int>>* sizesPx;
};

std::string sizeText(std::pair<int, int> sizePx) {
  return std::to_string(sizePx.first) + "x" + std::to_string(sizePx.second);
}

/// The requests in negotiateRawStream's order, each format once.
std::vector<RawRequest> rawRequests(const std::vector<OfferedFormat>& offered,
                                    const std::string& first) {
  std::vector<RawRequest> requests;
  const auto add = [&](const std::string& format, const OfferedFormat& parent) {
    for (const RawRequest& request : requests)
      if (request.format == format) return;
    requests.push_back({format, &parent.sizesPx});
  };
  const auto addWithTwin = [&](const OfferedFormat& format) {
    if (format.decodable) add(format.name, format);
    if (const std::optional<std::string> twin = unpackedRawFormatName(format.name))
      add(*twin, format);
  };
  for (const OfferedFormat& format : offered)
    if (format.name == first) addWithTwin(format);
  for (const OfferedFormat& format : offered)
    if (format.decodable) addWithTwin(format);
  for (const OfferedFormat& format : offered)
    if (format.raw && !format.decodable) addWithTwin(format);
  return requests;
}

/// What validation did to one request that was not granted, for the notes and the reason.
std::string notGranted(const RawRequest& request, std::pair<int, int> modePx,
                       const RawValidation& validation) {
  const std::string asked = request.format + " " + sizeText(modePx);
  if (validation.refused) return asked + " refused";
  if (validation.format.find("_PISP_COMP") != std::string::npos)
    return asked + " -> " + validation.format +
           " (the Pi 5's PiSP compressed Bayer, lossy: not decoded)";
  return asked + " -> " + validation.format + " (not decoded)";
}

}  // namespace

RawStreamChoice negotiateRawStream(const std::vector<OfferedFormat>& offered,
                                   std::string_view proposedFormat, int wantedWidthPx,
                                   int wantedHeightPx, const RawValidator& validate) {
  const RawStreamChoice byName =
      chooseRawStream(offered, proposedFormat, wantedWidthPx, wantedHeightPx);
  const std::vector<RawRequest> requests = rawRequests(offered, byName.format);
  if (requests.empty()) return byName;  // no RAW, or none decodable and no twin to ask for
  RawStreamChoice choice;
  for (const RawRequest& request : requests) {
    const std::pair<int, int> modePx =
        chooseBayerSize(*request.sizesPx, wantedWidthPx, wantedHeightPx)
            .value_or(std::pair{2 * wantedWidthPx, 2 * wantedHeightPx});
    const RawValidation validation = validate(request.format, modePx);
    if (!validation.refused && bayerFormatFromLibcameraName(validation.format)) {
      choice.format = validation.format;
      choice.requested = request.format;
      choice.modePx = validation.modePx;
      choice.deliveredPx = {validation.modePx.first / 2, validation.modePx.second / 2};
      if (!choice.notes.empty() || validation.format != request.format)
        choice.notes.push_back(request.format + " " + sizeText(modePx) + " granted as " +
                               validation.format + " " + sizeText(validation.modePx));
      return choice;
    }
    choice.notes.push_back(notGranted(request, modePx, validation));
  }
  choice.reason = "validation granted no RAW format slicecap decodes (";
  for (std::size_t i = 0; i < choice.notes.size(); ++i)
    choice.reason += (i > 0 ? "; " : "") + choice.notes[i];
  choice.reason += "): the processed stream is used instead";
  choice.notes.clear();
  return choice;
}

std::vector<std::string> describeModes(const CameraModes& modes) {
  std::vector<std::string> lines{modes.id};
  if (modes.formats.empty()) lines.push_back("  (no formats listed)");
  for (const OfferedFormat& format : modes.formats) {
    std::string line = "  " + format.name;
    if (format.raw) line += format.decodable ? " (RAW, decoded)" : " (RAW, not decoded)";
    line += ":";
    if (format.sizesPx.empty()) line += " sizes as a range";
    for (const auto& [widthPx, heightPx] : format.sizesPx)
      line += " " + std::to_string(widthPx) + "x" + std::to_string(heightPx);
    lines.push_back(line);
  }
  return lines;
}

const CameraModes* findLibcameraCamera(const std::vector<CameraModes>& cameras,
                                       const std::string& cameraId) {
  for (const CameraModes& camera : cameras)
    if (cameraId.empty() || camera.id == "libcamera: " + cameraId) return &camera;
  return nullptr;
}

}  // namespace slicecap::hal
