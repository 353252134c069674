// The texture store's frame files: their byte layout (docs/btf-format.md), written and read.
#include "texture_frame_file.hpp"

#include <Imath/half.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::btf::frame_file {
namespace {

namespace fs = std::filesystem;

void append(std::string& out, const void* data, std::size_t bytes) {
  out.append(static_cast<const char*>(data), bytes);
}

}  // namespace

std::size_t frameFileBytes(int resolution) {
  return sizeof kFrameMagic + sizeof(FrameHeader) +
         std::size_t(resolution) * resolution * 3 * sizeof(std::uint16_t) + sizeof(std::uint32_t);
}

std::string encodeFrame(const SliceId& slice, int resolution, std::uint64_t sequence,
                        const TextureFrame& frame) {
  FrameHeader header;
  header.kind = static_cast<std::int32_t>(slice.kind);
  header.thetaIDeg = slice.elevations.thetaIDeg;
  header.thetaVDeg = slice.elevations.thetaVDeg;
  header.resolution = resolution;
  header.sequence = sequence;
  header.sliceParameterDeg = frame.sliceParameterDeg;
  for (int k = 0; k < 3; ++k) {
    header.cameraMm[k] = frame.cameraMm[k];
    header.lightMm[k] = frame.lightMm[k];
  }
  std::string out;
  out.reserve(frameFileBytes(resolution));
  append(out, kFrameMagic, sizeof kFrameMagic);
  append(out, &header, sizeof header);
  for (float value : frame.texels) {
    const std::uint16_t bits = Imath::half(value).bits();
    append(out, &bits, sizeof bits);
  }
  const std::uint32_t crc = io::crc32(out);
  append(out, &crc, sizeof crc);
  return out;
}

std::string readWhole(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::IoError(path.string() + ": cannot open");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw io::IoError(path.string() + ": cannot read");
  return bytes;
}

FrameHeader readFrameHeader(const fs::path& path, int resolution) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::IoError(path.string() + ": cannot open: " + std::strerror(errno));
  std::error_code error;
  const auto size = fs::file_size(path, error);
  if (error) throw io::IoError(path.string() + ": cannot read its size: " + error.message());
  if (size != frameFileBytes(resolution))
    throw BadFrame(path.string() + ": torn or not a frame of this store (" + std::to_string(size) +
                   " bytes, " + std::to_string(frameFileBytes(resolution)) + " expected)");
  char magic[sizeof kFrameMagic];
  FrameHeader header;
  in.read(magic, sizeof magic);
  in.read(reinterpret_cast<char*>(&header), sizeof header);
  if (!in) throw io::IoError(path.string() + ": cannot read");
  if (std::memcmp(magic, kFrameMagic, sizeof magic) != 0)
    throw BadFrame(path.string() + ": not a slicecap texture frame");
  if (header.resolution != resolution)
    throw BadFrame(path.string() + ": " + std::to_string(header.resolution) +
                   " texels across, the store has " + std::to_string(resolution));
  if (header.kind != static_cast<int>(SliceKind::Axial) &&
      header.kind != static_cast<int>(SliceKind::Diagonal))
    throw BadFrame(path.string() + ": no axial or diagonal slice in its header");
  if (!std::isfinite(header.sliceParameterDeg))
    throw BadFrame(path.string() + ": its slice parameter is not a number");
  // Every texel's light and view directions are taken from these positions: one non-finite
  // coordinate would poison its bin's mean and stop the reconstruction.
  const auto finite = [](const double(&position)[3]) {
    return std::isfinite(position[0]) && std::isfinite(position[1]) && std::isfinite(position[2]);
  };
  if (!finite(header.cameraMm))
    throw BadFrame(path.string() + ": its camera position is not a finite number");
  if (!finite(header.lightMm))
    throw BadFrame(path.string() + ": its LED position is not a finite number");
  return header;
}

TextureFrame readFrame(const fs::path& path, int resolution) {
  const std::string bytes = readWhole(path);
  if (bytes.size() != frameFileBytes(resolution))
    throw io::IoError(path.string() + ": torn (" + std::to_string(bytes.size()) + " bytes, " +
                      std::to_string(frameFileBytes(resolution)) + " expected)");
  std::uint32_t crc = 0;
  std::memcpy(&crc, bytes.data() + bytes.size() - sizeof crc, sizeof crc);
  if (crc != io::crc32(std::string_view(bytes).substr(0, bytes.size() - sizeof crc)))
    throw io::IoError(path.string() +
                      ": checksum mismatch (the file is damaged; delete it to go "
                      "on without this frame)");
  FrameHeader header;
  std::memcpy(&header, bytes.data() + sizeof kFrameMagic, sizeof header);
  TextureFrame frame;
  frame.sliceParameterDeg = header.sliceParameterDeg;
  frame.cameraMm = Eigen::Vector3d(header.cameraMm[0], header.cameraMm[1], header.cameraMm[2]);
  frame.lightMm = Eigen::Vector3d(header.lightMm[0], header.lightMm[1], header.lightMm[2]);
  const std::size_t values = std::size_t(resolution) * resolution * 3;
  frame.texels.resize(values);
  const char* texels = bytes.data() + sizeof kFrameMagic + sizeof header;
  for (std::size_t i = 0; i < values; ++i) {
    Imath::half h;
    std::uint16_t bits;
    std::memcpy(&bits, texels + i * sizeof bits, sizeof bits);
    h.setBits(bits);
    frame.texels[i] = static_cast<float>(h);
  }
  return frame;
}

}  // namespace slicecap::btf::frame_file
