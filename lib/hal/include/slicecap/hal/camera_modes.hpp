// What a camera offers, for `slicecapd --check-hardware`: its formats with their sizes (a RAW
// format's sizes are the sensor's modes) and which RAW stream slicecap would take for a request.
#pragma once

#include <functional>
#include <optional>
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

/// \brief The RAW stream slicecap takes for a request, or why none.
struct RawStreamChoice {
  std::string format;                 ///< empty: no RAW stream is taken
  std::pair<int, int> modePx{0, 0};   ///< the sensor mode's mosaic size
  std::pair<int, int> deliveredPx{0, 0};  ///< the frames' size after 2 x 2 binning
  /// Why no RAW stream is taken: an undecodable format named (PiSP compressed), or that the
  /// camera offers none.
  std::string reason;
  /// negotiateRawStream only: the format asked for in the granted request (a Pi 5: SRGGB10,
  /// granted as SRGGB16; a Pi 4: the same as `format`).
  std::string requested;
  /// negotiateRawStream only: what validation did to the formats asked for before (or with)
  /// the one granted, one sentence each ("SRGGB10_CSI2P -> RGGB_PISP_COMP1 (...)"); said with
  /// the configuration so the change is never silent.
  std::vector<std::string> notes;
};

/// \brief A camera and what it offers.
struct CameraModes {
  std::string id;  ///< prefixed with the backend ("libcamera: ...", "v4l2: /dev/video0 (...)")
  std::vector<OfferedFormat> formats;
  /// The RAW format the backend proposes first (libcamera's Raw role), empty when none.
  std::string proposedRawFormat;
  /// The RAW stream the camera's own validation grants at the size asked for
  /// (negotiateRawStream; libcamera). nullopt where the backend lists names only (V4L2, the
  /// model): chooseRawStream on `formats` stands for it.
  std::optional<RawStreamChoice> validatedRaw;
  /// The sensor's model (libcamera's properties::Model, e.g. "imx708"); empty where unknown.
  std::string sensorModel{};
};

/// \brief The RAW stream the libcamera backend asks for first for `wantedWidthPx` x
/// `wantedHeightPx`: the proposed format when decodable, else the first decodable one offered;
/// the mode chooseBayerSize picks among its sizes (twice the request when none are listed).
/// Pure, and by name only: what the camera's validation makes of it is negotiateRawStream's.
RawStreamChoice chooseRawStream(const std::vector<OfferedFormat>& offered,
                                std::string_view proposedFormat, int wantedWidthPx,
                                int wantedHeightPx);

/// \brief What a camera's configuration validation made of one RAW request.
struct RawValidation {
  bool refused = false;  ///< validation said the configuration is invalid
  std::string format;    ///< the format it left in the stream (libcamera's name)
  std::pair<int, int> modePx{0, 0};  ///< the mosaic size it left in the stream
};

/// \brief Validates a RAW stream of `format` at `modePx` as the camera would be configured
/// (libcamera: the stream's pixelFormat and size set, then CameraConfiguration::validate()).
using RawValidator =
    std::function<RawValidation(const std::string& format, std::pair<int, int> modePx)>;

/// \brief The RAW stream a camera grants, asked for and checked through `validate`: the formats
/// are asked for in turn until validation leaves one slicecap decodes; the last call to
/// `validate` is then the granted request. The order: chooseRawStream's choice, then its unpacked
/// twin (unpackedRawFormatName) where it is packed, then every other decodable format offered,
/// each followed by its twin, then the twins of undecodable offered formats (a PiSP compressed
/// one). The twin is asked for at its packed parent's mode. A Pi 4 grants the packed proposal
/// as it is; a Pi 5 replaces it by its lossy PISP_COMP1 coding and then grants the unpacked
/// twin as 16-bit words (libcamera's PiSP pipeline, pisp.cpp platformValidate: "We cannot output
/// CSI2 packed or non 16-bit output from the frontend"). The granted format, the mode
/// validation left, `requested` and `notes` are set; when nothing decodable is granted, `reason`
/// names each request and what it became, ending ": the processed stream is used instead".
RawStreamChoice negotiateRawStream(const std::vector<OfferedFormat>& offered,
                                   std::string_view proposedFormat, int wantedWidthPx,
                                   int wantedHeightPx, const RawValidator& validate);

/// \brief The report's lines for a camera: its id, then one line per format with its sizes, RAW
/// formats marked as decoded or not.
std::vector<std::string> describeModes(const CameraModes& modes);

/// \brief An OfferedFormat named `name` with these sizes; raw and decodable from the name.
OfferedFormat offeredFormat(std::string name, std::vector<std::pair<int, int>> sizesPx);

/// \brief Among libcameraModes' cameras, the one `cameraId` names (camera_device; empty: the
/// first, as libcamera opens it); nullptr when none.
const CameraModes* findLibcameraCamera(const std::vector<CameraModes>& cameras,
                                       const std::string& cameraId);

}  // namespace slicecap::hal
