// OpenEXR reading and writing of the ABRDF table.
#include "slicecap/io/abrdf_exr.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "input_file.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "table_values.hpp"

namespace slicecap::io {
namespace {

constexpr const char* kPrefix = "slicecap:";
constexpr const char* kChannels[3] = {"R", "G", "B"};
constexpr int kSize = Abrdf::kDirections;

IoError error(const std::filesystem::path& path, const std::string& what) {
  return IoError(path.string() + ": " + what);
}

// The EXR encoded in memory (OpenEXR seeks back to fill in the line offsets), then written out
// through writeStreamReplacing: OpenEXR's own file stream flushes its last bytes in its
// destructor, where a failed write (disk full) goes unreported.
class MemoryExrStream : public Imf::OStream {
 public:
  explicit MemoryExrStream(const char* name) : Imf::OStream(name) {}
  void write(const char c[], int n) override {
    const std::size_t count = static_cast<std::size_t>(n);
    if (position_ + count > bytes_.size()) bytes_.resize(position_ + count);
    std::memcpy(bytes_.data() + position_, c, count);
    position_ += count;
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = static_cast<std::size_t>(position); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
  std::size_t position_ = 0;
};

}  // namespace

void writeAbrdfExr(const std::filesystem::path& path, const Abrdf& table,
                   const ExrAttributes& attributes) {
  // The reader refuses such a file: no command may write one.
  if (const auto problem = firstInvalidValue(table))
    throw error(path, "not written: a " + *problem);
  Imf::Header header(kSize, kSize);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : kChannels)
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  ExrAttributes all = attributes;
  all["layout"] = "bonn81";
  all["quantity"] = "brdf";
  all.try_emplace("version", kVersion);
  for (const auto& [key, value] : all)
    header.insert(kPrefix + key, Imf::StringAttribute(value));

  // The frame buffer reads straight from the table: row = light, column = view, 3 floats a pixel.
  const float* base = table.values().data();
  constexpr std::size_t xStride = 3 * sizeof(float);
  constexpr std::size_t yStride = xStride * kSize;
  Imf::FrameBuffer frame;
  for (int c = 0; c < 3; ++c) {
    frame.insert(kChannels[c],
                 Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(base + c)),
                            xStride, yStride));
  }
  MemoryExrStream encoded(path.c_str());
  try {
    // The line offset table is written when the file object is destroyed: before the bytes are
    // taken.
    Imf::OutputFile file(encoded, header);
    file.setFrameBuffer(frame);
    file.writePixels(kSize);
  } catch (const std::exception& e) {
    throw error(path, std::string("cannot write EXR: ") + e.what());
  }
  writeStreamReplacing(path, [&](std::ostream& out) {
    out.write(encoded.bytes().data(), static_cast<std::streamsize>(encoded.bytes().size()));
  });
}

namespace {

// An ABRDF is 81 x 81 (light rows x view columns) with R, G and B channels.
void checkAbrdfShape(const Imf::Header& header, const std::filesystem::path& path) {
  const Imath::Box2i window = header.dataWindow();
  const int width = window.max.x - window.min.x + 1;
  const int height = window.max.y - window.min.y + 1;
  if (width != kSize || height != kSize) {
    throw error(path, "ABRDF EXR must be 81 x 81 (light rows x view columns), got " +
                          std::to_string(height) + " x " + std::to_string(width));
  }
  for (const char* name : kChannels) {
    if (!header.channels().findChannel(name)) {
      throw error(path, std::string("ABRDF EXR has no channel ") + name + " (needs R, G, B)");
    }
  }
}

// The header's slicecap: string attributes (prefix dropped); the layout and quantity must say
// this is a slicecap ABRDF.
ExrAttributes slicecapAttributes(const Imf::Header& header, const std::filesystem::path& path) {
  ExrAttributes found;
  for (auto it = header.begin(); it != header.end(); ++it) {
    const std::string name = it.name();
    if (name.rfind(kPrefix, 0) != 0) continue;
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) {
      found[name.substr(std::string(kPrefix).size())] = s->value();
    }
  }
  auto require = [&](const std::string& key, const std::string& expected) {
    auto it = found.find(key);
    if (it == found.end()) {
      throw error(path, "missing header attribute " + std::string(kPrefix) + key + " (expected \"" +
                            expected + "\"); is this a slicecap ABRDF?");
    }
    if (it->second != expected) {
      throw error(path, "header attribute " + std::string(kPrefix) + key + " is \"" + it->second +
                            "\", expected \"" + expected + "\"");
    }
  };
  require("layout", "bonn81");
  require("quantity", "brdf");
  return found;
}

// Reads the R, G, B channels of the (shape-checked) file into `table`.
void readAbrdfPixels(Imf::InputFile& file, Abrdf& table) {
  const Imath::Box2i window = file.header().dataWindow();
  float* base = table.values().data();
  constexpr std::size_t xStride = 3 * sizeof(float);
  constexpr std::size_t yStride = xStride * kSize;
  // OpenEXR addresses pixels by their data-window coordinates, so the base is shifted by its
  // origin.
  const std::ptrdiff_t originOffset = -std::ptrdiff_t(window.min.x) * std::ptrdiff_t(xStride) -
                                      std::ptrdiff_t(window.min.y) * std::ptrdiff_t(yStride);
  Imf::FrameBuffer frame;
  for (int c = 0; c < 3; ++c) {
    frame.insert(
        kChannels[c],
        Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + c) + originOffset, xStride, yStride));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
}

}  // namespace

Abrdf readAbrdfExr(const std::filesystem::path& path, ExrAttributes* attributes) {
  refuseDirectory(path, "an ABRDF EXR");
  Abrdf table;
  try {
    Imf::InputFile file(path.c_str());
    checkAbrdfShape(file.header(), path);
    ExrAttributes found = slicecapAttributes(file.header(), path);
    readAbrdfPixels(file, table);
    if (attributes) *attributes = std::move(found);
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw error(path, std::string("cannot read EXR: ") + e.what());
  }
  if (const auto problem = firstInvalidValue(table)) throw error(path, *problem);
  return table;
}

}  // namespace slicecap::io
