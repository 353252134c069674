// What a camera offers, for `slicecapd --check-hardware`: its formats with their sizes (a RAW
// format's sizes are the sensor's modes) and which RAW stream slicecap would take for a request.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace slicecap::hal {

/// \brief One pixel format a camera offers.
struct OfferedFormat {
  std::string name;       ///< libcamera's name ("SRGGB10_CSI2P", "YUYV"), or a V4L2 format's
  bool raw = false;       ///< a RAW Bayer format (isRawFormatName), decodable or not
  bool decodable = false; ///< a RAW format decodeBayer reads
  /// Discrete sizes, width x height; empty when the backend gives only a range.
  std::vector<std::pair<int, int>> sizesPx;
};

/// \brief A camera and what it offers.
struct CameraModes {
  std::string id;  ///< prefixed with the backend ("libcamera: ...", "v4l2: /dev/video0 (...)")
  std::vector<OfferedFormat> formats;
  /// The RAW format the backend proposes first (libcamera's Raw role), empty when none.
  std::string proposedRawFormat;
};

/// \brief The RAW stream slicecap takes for a request, or why none.
struct RawStreamChoice {
  std::string format;                 ///< empty: no RAW stream is taken
  std::pair<int, int> modePx{0, 0};   ///< the sensor mode's mosaic size
  std::pair<int, int> deliveredPx{0, 0};  ///< the frames' size after 2 x 2 binning
  /// Why no RAW stream is taken: an undecodable format named (PiSP compressed), or that the
  /// camera offers none.
  std::string reason;
};

/// \brief The RAW stream the libcamera backend configures for `wantedWidthPx` x
/// `wantedHeightPx`: the proposed format when decodable, else the first decodable one offered;
/// the mode chooseBayerSize picks among its sizes (twice the request when none are listed).
/// Pure: the backend and the hardware check share it, so the check reports what a sweep takes.
RawStreamChoice chooseRawStream(const std::vector<OfferedFormat>& offered,
                                std::string_view proposedFormat, int wantedWidthPx,
                                int wantedHeightPx);

/// \brief The report's lines for a camera: its id, then one line per format with its sizes, RAW
/// formats marked as decoded or not.
std::vector<std::string> describeModes(const CameraModes& modes);

/// \brief An OfferedFormat named `name` with these sizes; raw and decodable from the name.
OfferedFormat offeredFormat(std::string name, std::vector<std::pair<int, int>> sizesPx);

}  // namespace slicecap::hal
