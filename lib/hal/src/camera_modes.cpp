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

}  // namespace slicecap::hal
