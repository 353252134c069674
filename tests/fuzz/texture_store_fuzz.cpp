// libFuzzer target: any bytes as a captured texture (btf::TextureStore, docs/btf-format.md
// "Texture store"), opened read-only and combined as `slicecap btf` does on an export. The input
// is texture.json, optionally followed by a frame file after a line "--frame--" (the file as it
// is) or "--sealed frame--" (its CRC-32 appended by the harness, so that the fuzzer's texels and
// header get past the checksum). The frame goes into the folder its header's slice names, so that
// it is read. Opening and combining either work or throw io::IoError naming the file (the error a
// person sees); anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "fuzz_file.hpp"
#include "slicecap/btf/texture_store.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace {

// The folder a frame whose header says kind, theta_i, theta_v is read from (bytes 8..19).
std::string folderOf(std::string_view frame) {
  std::int32_t fields[3] = {0, 0, 0};
  if (frame.size() >= 8 + sizeof fields) std::memcpy(fields, frame.data() + 8, sizeof fields);
  const char* kind = fields[0] == 0 ? "axial" : fields[0] == 1 ? "diagonal" : "point";
  return std::string(kind) + "-" + std::to_string(fields[1]) + "-" + std::to_string(fields[2]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap;
  namespace fs = std::filesystem;
  static const fs::path dir = fuzz::scratchDir("texture") / "texture";
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  fs::create_directories(dir);

  const std::string_view input = fuzz::asText(data, size);
  std::string_view manifest = input, frame;
  bool seal = false;
  for (const auto& [separator, sealed] :
       {std::pair{std::string_view("\n--frame--\n"), false},
        std::pair{std::string_view("\n--sealed frame--\n"), true}}) {
    const std::size_t at = input.find(separator);
    if (at != std::string_view::npos && at < manifest.size()) {
      manifest = input.substr(0, at);
      frame = input.substr(at + separator.size());
      seal = sealed;
    }
  }
  fuzz::writeBytes(dir / btf::kTextureStoreManifest, manifest);
  if (manifest.size() != input.size()) {
    std::string bytes(frame);
    if (seal) {
      const std::uint32_t crc = io::crc32(bytes);
      bytes.append(reinterpret_cast<const char*>(&crc), sizeof crc);
    }
    fs::create_directories(dir / folderOf(bytes));
    fuzz::writeBytes(dir / folderOf(bytes) / "b00-00000001.tex", bytes);
  }
  try {
    const btf::TextureStore store = btf::TextureStore::open(dir, btf::StoreAccess::ReadOnly);
    (void)store.grid().texelCount();
    (void)store.storedBytes();
    for (const SliceId& slice : store.slices())
      (void)store.filledBins(slice);
    (void)store.combine();
  } catch (const io::IoError&) {
  }
  return 0;
}
