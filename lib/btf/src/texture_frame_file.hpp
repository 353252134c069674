// The texture store's frame files: their byte layout (docs/btf-format.md), written and read.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "slicecap/btf/btf_error.hpp"
#include "slicecap/btf/texture_store.hpp"

namespace slicecap::btf::frame_file {

inline constexpr char kFrameMagic[8] = {'S', 'C', 'T', 'E', 'X', 'F', '0', '1'};
inline constexpr const char* kFrameExtension = ".tex";

// A frame file: magic, the header below (little-endian, as every platform slicecap runs on),
// N^2 x RGB half floats, CRC-32 of everything before it.
struct FrameHeader {
  std::int32_t kind = 0;
  std::int32_t thetaIDeg = 0;
  std::int32_t thetaVDeg = 0;
  std::int32_t resolution = 0;
  std::uint64_t sequence = 0;
  double sliceParameterDeg = 0.0;
  double cameraMm[3] = {0, 0, 0};
  double lightMm[3] = {0, 0, 0};
};
static_assert(std::endian::native == std::endian::little, "the frame files are little-endian");
// The header is written as it lies in memory: docs/btf-format.md's table is this layout.
static_assert(sizeof(FrameHeader) == 80 && offsetof(FrameHeader, sequence) == 16 &&
                  offsetof(FrameHeader, sliceParameterDeg) == 24 &&
                  offsetof(FrameHeader, cameraMm) == 32 && offsetof(FrameHeader, lightMm) == 56,
              "the frame header's layout is the documented one");

// A frame file whose content is wrong (torn by a power cut, damaged, not a frame): unlike a file
// that cannot be opened, it can never become readable, so mending the store removes it.
struct BadFrame : BtfError {
  using BtfError::BtfError;
};

/// \brief The size of a frame file of `resolution`^2 texels.
std::size_t frameFileBytes(int resolution);

/// \brief The bytes of a frame file.
std::string encodeFrame(const SliceId& slice, int resolution, std::uint64_t sequence,
                        const TextureFrame& frame);

/// \brief The whole file. io::IoError when it cannot be opened or read.
std::string readWhole(const std::filesystem::path& path);

// The header of a frame file, checked against the layout without reading its texels (opening a
// store must stay quick); the CRC is checked when the texels are read. io::IoError when the file
// cannot be opened or read, BadFrame when what it holds is wrong.
FrameHeader readFrameHeader(const std::filesystem::path& path, int resolution);

/// \brief The frame with its texels, the CRC checked. io::IoError or BadFrame as readFrameHeader.
TextureFrame readFrame(const std::filesystem::path& path, int resolution);

}  // namespace slicecap::btf::frame_file
