// RAW (Bayer) sensor buffers to linear RGB: the CFA orders and packings libcamera and V4L2
// deliver, the black level taken off, each 2 x 2 cell binned into one RGB pixel.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "slicecap/core/image.hpp"
#include "slicecap/hal/raw_frame.hpp"

namespace slicecap::hal {

/// \brief The colour filter array's order: the colours of the top-left 2 x 2 cell, row by row
/// (RGGB: R G on even rows, G B on odd rows).
enum class BayerOrder { Rggb, Grbg, Gbrg, Bggr };

/// \brief How samples are stored. Unpacked16: one little-endian 16-bit word a sample, the value
/// in the low bits (libcamera SRGGB10/12/16, V4L2 SRGGB10/12/16). Csi2Packed: MIPI CSI-2
/// packing (libcamera SRGGB10_CSI2P/12_CSI2P, V4L2 'pRAA'/'pRCC'): 10-bit, 4 samples in 5 bytes
/// (the 8 high bits of each, then a byte of their 2 low bits, sample 0 in bits 1..0); 12-bit,
/// 2 samples in 3 bytes (the 8 high bits of each, then their 4 low bits, sample 0 in bits 3..0).
/// Linux media documentation, "V4L2_PIX_FMT_SRGGB10P" and "V4L2_PIX_FMT_SRGGB12P"
/// (docs.kernel.org/userspace-api/media/v4l/pixfmt-srggb10p.html, pixfmt-srggb12p.html).
enum class BayerPacking { Unpacked16, Csi2Packed };

/// \brief A Bayer layout slicecap decodes: 10 or 12 bits in either packing, or 16 unpacked.
struct BayerFormat {
  BayerOrder order = BayerOrder::Rggb;
  int bitDepth = 10;
  BayerPacking packing = BayerPacking::Csi2Packed;
  friend bool operator==(const BayerFormat&, const BayerFormat&) = default;
};

/// \brief The black level of each CFA colour on a 16-bit scale (as if samples ran 0..65535), in
/// libcamera's order R, Gr (the green on red rows), Gb, B: what libcamera's SensorBlackLevels
/// metadata reports. Scaled to a sample's bit depth by 2^(bitDepth - 16).
struct BayerBlackLevels {
  std::array<double, 4> levels16{};
  /// \brief The same level for every colour.
  static BayerBlackLevels uniform(double level16) { return {{level16, level16, level16, level16}}; }
};

/// \brief Raspberry Pi's default black level, 64 at 10 bits = 4096 on the 16-bit scale (the
/// `rpi.black_level` algorithm's default in libcamera's Raspberry Pi IPA, black_level.cpp; the
/// IMX708 and IMX219 tuning files say the same): used when a camera does not report its own.
/// rpicam-apps' DNG writer does the same: SensorBlackLevels (R, Gr, Gb, B) when the frame has
/// it, else 4096 scaled to the sample's bits.
inline constexpr double kDefaultBlackLevel16 = 4096.0;

/// \brief One RAW frame's bytes as the device delivered them: the mosaic's size in sensor pixels.
struct BayerFrameView {
  BayerFormat format;
  int widthPx = 0;
  int heightPx = 0;
  std::span<const std::uint8_t> bytes;
  std::size_t strideBytes = 0;
};

/// \brief libcamera's name of the format ("SRGGB10_CSI2P", "SBGGR12", ...).
std::string bayerFormatName(const BayerFormat& format);

/// \brief The format libcamera names so (PixelFormat::toString()), when slicecap decodes it.
std::optional<BayerFormat> bayerFormatFromLibcameraName(std::string_view name);

/// \brief The format of a V4L2 fourcc (V4L2_PIX_FMT_SRGGB10, _SRGGB10P, ...), when slicecap
/// decodes it.
std::optional<BayerFormat> bayerFormatFromV4l2(std::uint32_t fourcc);

/// \brief True for names of RAW Bayer formats, decodable or not: the S????NN family and their
/// packings (_CSI2P, _IPU3, ...), and Raspberry Pi 5's PiSP compressed formats (*_PISP_COMP*).
bool isRawFormatName(std::string_view name);

/// \brief Why a RAW format is not decoded, in a sentence naming it and the fallback (the
/// processed stream); empty when it is decoded. PiSP's compressed formats (RGGB_PISP_COMP1 and
/// its orders, the Pi 5's default RAW) are a lossy proprietary coding: not decoded.
std::string undecodableRawReason(std::string_view name);

/// \brief The unpacked format (16-bit words) that holds the same samples as the packed RAW
/// format `name`, which a pipeline that replaces packed RAW grants instead: "SRGGB10" for
/// "SRGGB10_CSI2P" (the same bit depth, so libcamera's Raspberry Pi pipelines pick the same
/// sensor mode), "SRGGB16" for the Pi 5's compressed "RGGB_PISP_COMP1" (what its frontend writes
/// uncompressed). nullopt for a name that is not a packed RAW format (already unpacked, an
/// unknown packing such as _IPU3, not RAW).
std::optional<std::string> unpackedRawFormatName(std::string_view name);

/// \brief The smallest stride a row of `widthPx` samples needs (CSI-2 rows end on a whole
/// group: 5 bytes per 4 samples, 3 per 2).
std::size_t minimalBayerStrideBytes(const BayerFormat& format, int widthPx);

/// \brief Of the mosaic sizes a camera offers (its sensor modes), the one whose 2 x 2 binned
/// size comes nearest `wantedWidthPx` x `wantedHeightPx`: the aspect ratio first, then the
/// pixel count on a log scale (the IMX708's 2304 x 1296 for 1280 x 720). nullopt when none.
std::optional<std::pair<int, int>> chooseBayerSize(const std::vector<std::pair<int, int>>& offered,
                                                   int wantedWidthPx, int wantedHeightPx);

/// \brief The sample value a decoded RAW frame stores for the sensor's black (Frame::black16):
/// 4096 of 65535, 1/16 of the range, about 20 times the read noise of a Pi camera's sensor
/// (2-3 codes of 10 bits). Samples below black, the read noise of a dark pixel, are stored below
/// it instead of clipped to 0, which biased the mean of a dark area upwards (by 0.4 times the
/// read noise where the light is at black: the LED-off frames that are subtracted from every
/// sample).
inline constexpr std::uint16_t kDecodedBlack16 = 4096;

/// \brief Decodes a mosaic into linear RGB at half its size (odd last rows or columns dropped):
/// each sample has its colour's black level subtracted and is scaled so that black..the
/// format's largest code maps to kDecodedBlack16..65535; each 2 x 2 cell gives R, the mean of
/// its two greens, B. Below black, a value is kept down to kDecodedBlack16 under it (0 stored)
/// and only clips beyond: the frame's black16 is kDecodedBlack16, and linear16Value() reads it.
/// Returns a 3-channel 16-bit Image (PixelEncoding::Linear16). Throws RawFrameError naming the
/// format, the plane and the bytes when the buffer is shorter than its stride and height need,
/// the stride is below a row's bytes, the mosaic is under 2 x 2, or a black level is not below
/// the largest code.
Image decodeBayer(const BayerFrameView& raw, const BayerBlackLevels& black);

/// \brief Packs a mosaic of codes (row-major, `widthPx` x `heightPx`, each < 2^bitDepth) into
/// the format's bytes with `strideBytes` per row (0: the minimal stride; padding is zero): what
/// a sensor writes, for the camera model. Throws HalError on a size mismatch or a
/// stride below the minimal one.
std::vector<std::uint8_t> packBayer(const BayerFormat& format, int widthPx, int heightPx,
                                    std::span<const std::uint16_t> codes,
                                    std::size_t strideBytes = 0);

}  // namespace slicecap::hal
