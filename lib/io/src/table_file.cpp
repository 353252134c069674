// Raw float32 tables and the extension-based table reader.
#include "slicecap/io/table_file.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "input_file.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "table_values.hpp"

namespace slicecap::io {
namespace {

constexpr std::size_t kBytes = Abrdf::kValueCount * sizeof(float);

// The file is little-endian; the host may not be.
std::uint32_t toLittleEndian(std::uint32_t v) {
  if constexpr (std::endian::native == std::endian::little) return v;
  return ((v & 0xffu) << 24) | ((v & 0xff00u) << 8) | ((v >> 8) & 0xff00u) | (v >> 24);
}

}  // namespace

Abrdf readF32Table(const std::filesystem::path& path) {
  refuseDirectory(path, "a .f32 table");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open table");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() != kBytes) {
    throw IoError(path.string() + ": a .f32 table must hold 81*81*3 float32 = " +
                  std::to_string(kBytes) + " bytes, this one has " + std::to_string(bytes.size()));
  }
  Abrdf table;
  std::span<float> values = table.values();
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word;
    std::memcpy(&word, bytes.data() + i * sizeof(float), sizeof word);
    values[i] = std::bit_cast<float>(toLittleEndian(word));
  }
  if (const auto problem = firstInvalidValue(table)) throw IoError(path.string() + ": " + *problem);
  return table;
}

void writeF32Table(const std::filesystem::path& path, const Abrdf& table) {
  // The reader refuses such a file: no command may write one.
  if (const auto problem = firstInvalidValue(table))
    throw IoError(path.string() + ": not written: a " + *problem);
  writeStreamReplacing(path, [&](std::ostream& out) {
    for (float v : table.values()) {
      const std::uint32_t word = toLittleEndian(std::bit_cast<std::uint32_t>(v));
      out.write(reinterpret_cast<const char*>(&word), sizeof word);
    }
  });
}

Abrdf readTable(const std::filesystem::path& path) {
  refuseDirectory(path, "a table (.exr or .f32)");
  const std::string extension = path.extension().string();
  if (extension == ".exr") return readAbrdfExr(path);
  if (extension == ".f32") return readF32Table(path);
  throw IoError(path.string() + ": unknown table format '" + extension +
                "' (expected .exr or .f32)");
}

}  // namespace slicecap::io
