// The texture store: one atomically written file per kept frame, an in-memory index, the bins'
// keep rule re-applied on opening.
#include "slicecap/btf/texture_store.hpp"

#include <Imath/half.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "slicecap/capture/azimuth_bins.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/io/target_json.hpp"

namespace slicecap::btf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kBinWidthDeg = 15.0;  // as the window-average bins (capture::AzimuthBins)
constexpr char kFrameMagic[8] = {'S', 'C', 'T', 'E', 'X', 'F', '0', '1'};
constexpr const char* kFrameExtension = ".tex";

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
struct BadFrame : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::size_t frameFileBytes(int resolution) {
  return sizeof kFrameMagic + sizeof(FrameHeader) +
         std::size_t(resolution) * resolution * 3 * sizeof(std::uint16_t) + sizeof(std::uint32_t);
}

void append(std::string& out, const void* data, std::size_t bytes) {
  out.append(static_cast<const char*>(data), bytes);
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

std::string readWhole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::IoError(path.string() + ": cannot open");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw io::IoError(path.string() + ": cannot read");
  return bytes;
}

// The header of a frame file, checked against the layout without reading its texels (opening a
// store must stay quick); the CRC is checked when the texels are read. io::IoError when the file
// cannot be opened or read, BadFrame when what it holds is wrong.
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
    throw io::IoError(path.string() + ": checksum mismatch (the file is damaged; delete it to go "
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

json layoutJson(const TextureStoreLayout& layout) {
  return {{"format", "slicecap-texture-store"},
          {"version", 1},
          {"resolution", layout.resolution},
          {"frames_per_bin", layout.framesPerBin},
          {"bin_width_deg", kBinWidthDeg},
          {"window_mm",
           {{"x_min", layout.windowMm.xMinMm},
            {"y_min", layout.windowMm.yMinMm},
            {"x_max", layout.windowMm.xMaxMm},
            {"y_max", layout.windowMm.yMaxMm}}},
          {"texel_encoding", "float16le"},
          {"quantity", "brdf"},
          {"created_by", std::string("slicecap ") + kVersion}};
}

// A whole number of the manifest that fits an int (checkLayout then checks its range): nlohmann's
// get<int>() of 1e300 is undefined behaviour, and of 128.7 quietly 128.
int wholeNumber(const json& j, const char* key, const fs::path& manifest) {
  const json& value = j.at(key);
  if (value.is_number_unsigned() && std::in_range<int>(value.get<std::uint64_t>()))
    return static_cast<int>(value.get<std::uint64_t>());
  if (value.is_number_integer() && !value.is_number_unsigned() &&
      std::in_range<int>(value.get<std::int64_t>()))
    return static_cast<int>(value.get<std::int64_t>());
  throw io::IoError(manifest.string() + ": " + key + ": expected a whole number, got " +
                    value.dump());
}

TextureStoreLayout readLayout(const fs::path& manifest) {
  const json j = io::parseJson(readWhole(manifest), manifest.string());
  try {
    if (j.at("format") != "slicecap-texture-store")
      throw io::IoError(manifest.string() + ": format: not a slicecap texture store");
    if (j.at("version") != 1)
      throw io::IoError(manifest.string() + ": version: " + j.at("version").dump() +
                        " (this slicecap reads 1)");
    if (j.at("bin_width_deg").get<double>() != kBinWidthDeg)
      throw io::IoError(manifest.string() + ": bin_width_deg: only 15 is supported");
    // The frames' texels are read as these say: another encoding or quantity would be misread.
    if (j.at("texel_encoding") != "float16le")
      throw io::IoError(manifest.string() + ": texel_encoding: " + j.at("texel_encoding").dump() +
                        " (this slicecap reads \"float16le\")");
    if (j.at("quantity") != "brdf")
      throw io::IoError(manifest.string() + ": quantity: " + j.at("quantity").dump() +
                        " (this slicecap reads \"brdf\")");
    TextureStoreLayout layout;
    layout.resolution = wholeNumber(j, "resolution", manifest);
    layout.framesPerBin = wholeNumber(j, "frames_per_bin", manifest);
    const json& w = j.at("window_mm");
    layout.windowMm = {w.at("x_min").get<double>(), w.at("y_min").get<double>(),
                       w.at("x_max").get<double>(), w.at("y_max").get<double>()};
    return layout;
  } catch (const json::exception& e) {
    throw io::IoError(manifest.string() + ": " + e.what());
  }
}

void checkLayout(const TextureStoreLayout& layout) {
  TextureGrid(layout.resolution, layout.windowMm);  // throws for a bad resolution or window
  if (layout.framesPerBin < 1 || layout.framesPerBin > 64)
    throw std::invalid_argument("texture store: frames per bin must be in 1..64, not " +
                                std::to_string(layout.framesPerBin));
}

void removeQuietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove_all(path, ignored);
}

}  // namespace

TextureStore::TextureStore(fs::path directory, TextureStoreLayout layout, StoreAccess access)
    : directory_(std::move(directory)), layout_(layout), access_(access) {}

TextureStore TextureStore::openOrCreate(const fs::path& directory,
                                        const TextureStoreLayout& layout) {
  checkLayout(layout);
  const fs::path manifest = directory / kTextureStoreManifest;
  if (!fs::exists(manifest)) {
    io::createFoldersDurably(directory);
    io::writeFileAtomically(manifest, layoutJson(layout).dump(2) + "\n");
  }
  TextureStore store = open(directory);
  const TextureStoreLayout& found = store.layout();
  const auto describe = [](const TextureStoreLayout& l) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "%d texels across, %d frames a bin, window x %g..%g y %g..%g mm", l.resolution,
                  l.framesPerBin, l.windowMm.xMinMm, l.windowMm.xMaxMm, l.windowMm.yMinMm,
                  l.windowMm.yMaxMm);
    return std::string(text);
  };
  if (found.resolution != layout.resolution || !(found.windowMm == layout.windowMm) ||
      found.framesPerBin != layout.framesPerBin)
    throw io::IoError(manifest.string() + ": this session's texture has " + describe(found) +
                      "; asked now: " + describe(layout) +
                      " (one session has one texture: change the configuration or target back, "
                      "or start a new session)");
  return store;
}

TextureStore TextureStore::open(const fs::path& directory, StoreAccess access) {
  const fs::path manifest = directory / kTextureStoreManifest;
  if (!fs::exists(manifest))
    throw io::IoError(directory.string() + ": not a texture store (no " + kTextureStoreManifest +
                      ")");
  TextureStoreLayout layout = readLayout(manifest);
  try {
    checkLayout(layout);
  } catch (const std::invalid_argument& e) {
    throw io::IoError(manifest.string() + ": " + e.what());
  }
  TextureStore store(directory, layout, access);
  store.load();
  return store;
}

void TextureStore::load() {
  struct Found {
    SliceId slice;
    Entry entry;
  };
  std::vector<Found> found;
  const bool mend = access_ == StoreAccess::Mend;
  // A leftover is removed when mending, else just not read.
  const auto leftover = [&](const fs::path& path) {
    if (mend) removeQuietly(path);
    ++recovery_.leftovers;
  };
  std::error_code error;
  for (const fs::directory_entry& folder : fs::directory_iterator(directory_, error)) {
    if (!folder.is_directory()) {
      if (folder.path().extension() == ".tmp") leftover(folder.path());
      continue;
    }
    const std::string name = folder.path().filename().string();
    if (name.find(io::kDiscardedSuffix) != std::string::npos) {  // a redo cut off half-way
      leftover(folder.path());
      continue;
    }
    for (const fs::directory_entry& file : fs::directory_iterator(folder.path(), error)) {
      if (file.path().extension() == ".tmp") {  // a write cut off (or, read-only, under way)
        leftover(file.path());
        continue;
      }
      if (file.path().extension() != kFrameExtension) continue;
      try {
        const FrameHeader header = readFrameHeader(file.path(), layout_.resolution);
        const SliceId slice{static_cast<SliceKind>(header.kind),
                            {header.thetaIDeg, header.thetaVDeg}};
        if (folderName(slice) != name)
          throw BadFrame(file.path().string() + ": a frame of " + folderName(slice) +
                         " in the folder of another slice");
        found.push_back({slice, {header.sliceParameterDeg, header.sequence, file.path()}});
      } catch (const BadFrame& e) {
        recovery_.droppedFiles.push_back(e.what());
        if (mend) removeQuietly(file.path());
      }
    }
    if (error) break;
  }
  if (error) throw io::IoError(directory_.string() + ": cannot list: " + error.message());
  // In the order they were stored, through the keep rule: a crash between storing a frame and
  // deleting the one it replaced leaves both; the rule drops the replaced one again.
  std::sort(found.begin(), found.end(),
            [](const Found& a, const Found& b) { return a.entry.sequence < b.entry.sequence; });
  for (Found& f : found) {
    nextSequence_ = std::max(nextSequence_, f.entry.sequence + 1);
    const auto where = placeOf(f.slice, f.entry.parameterDeg);
    if (!where) {
      leftover(f.entry.file);
      continue;
    }
    std::vector<Entry>& bin = indexFor(f.slice)[static_cast<std::size_t>(where->first)];
    if (where->second < bin.size()) {  // it replaces a frame whose deletion a crash cut off
      leftover(bin[where->second].file);
      bin[where->second] = std::move(f.entry);
      continue;
    }
    bin.push_back(std::move(f.entry));
  }
}

TextureStore::SliceIndex& TextureStore::indexFor(const SliceId& slice) {
  SliceIndex& bins = index_[slice];
  if (bins.empty()) bins.resize(static_cast<std::size_t>(360.0 / kBinWidthDeg));
  return bins;
}

std::optional<std::pair<int, std::size_t>> TextureStore::placeOf(const SliceId& slice,
                                                                 double parameterDeg) const {
  const capture::AzimuthBins bins(slice.kind, kBinWidthDeg);
  const int bin = bins.binOf(parameterDeg);
  std::vector<double> kept;
  if (const auto found = index_.find(slice); found != index_.end())
    for (const Entry& e : found->second[static_cast<std::size_t>(bin)])
      kept.push_back(e.parameterDeg);
  const std::optional<std::size_t> slot =
      keepSlot(kept, parameterDeg, bin * kBinWidthDeg, layout_.framesPerBin);
  if (!slot) return std::nullopt;
  return std::make_pair(bin, *slot);
}

void TextureStore::place(const SliceId& slice, Entry entry, int bin, std::size_t slot) {
  std::vector<Entry>& kept = indexFor(slice)[static_cast<std::size_t>(bin)];
  if (slot == kept.size()) {
    kept.push_back(std::move(entry));
    return;
  }
  const fs::path replaced = kept[slot].file;
  kept[slot] = std::move(entry);
  std::error_code error;
  fs::remove(replaced, error);
  // Left behind, the replaced frame is dropped again by the keep rule when the store is opened.
}

bool TextureStore::wouldKeep(const SliceId& slice, double parameterDeg) const {
  return placeOf(slice, parameterDeg).has_value();
}

bool TextureStore::add(const SliceId& slice, const TextureFrame& frame) {
  if (access_ != StoreAccess::Mend)
    throw std::logic_error("texture store: " + directory_.string() + " was opened read-only");
  if (slice.kind != SliceKind::Axial && slice.kind != SliceKind::Diagonal)
    throw std::invalid_argument("texture store: only axial and diagonal slices have a texture");
  const std::size_t values = grid().texelCount() * 3;
  if (frame.texels.size() != values)
    throw std::invalid_argument("texture store: a frame of " + std::to_string(frame.texels.size()) +
                                " values, expected " + std::to_string(values));
  const auto where = placeOf(slice, frame.sliceParameterDeg);
  if (!where) return false;
  const fs::path folder = directory_ / folderName(slice);
  io::createFoldersDurably(folder);
  const std::uint64_t sequence = nextSequence_++;
  char name[40];
  std::snprintf(name, sizeof name, "b%02d-%08llu%s", where->first,
                static_cast<unsigned long long>(sequence), kFrameExtension);
  const fs::path file = folder / name;
  io::writeFileAtomically(file, encodeFrame(slice, layout_.resolution, sequence, frame));
  place(slice, {frame.sliceParameterDeg, sequence, file}, where->first, where->second);
  return true;
}

void TextureStore::discard(const SliceId& slice) {
  if (access_ != StoreAccess::Mend)
    throw std::logic_error("texture store: " + directory_.string() + " was opened read-only");
  // The index follows the disk: if the folder cannot be discarded, its frames stay known.
  io::discardFolderDurably(directory_ / folderName(slice));
  index_.erase(slice);
}

std::vector<SliceId> TextureStore::slices() const {
  std::vector<SliceId> out;
  for (const auto& [slice, bins] : index_)
    if (frameCount(slice) > 0) out.push_back(slice);
  return out;
}

int TextureStore::filledBins(const SliceId& slice) const {
  const auto found = index_.find(slice);
  if (found == index_.end()) return 0;
  return static_cast<int>(std::count_if(found->second.begin(), found->second.end(),
                                        [](const auto& bin) { return !bin.empty(); }));
}

std::size_t TextureStore::frameCount(const SliceId& slice) const {
  const auto found = index_.find(slice);
  if (found == index_.end()) return 0;
  std::size_t count = 0;
  for (const auto& bin : found->second)
    count += bin.size();
  return count;
}

std::size_t TextureStore::frameCount() const {
  std::size_t count = 0;
  for (const auto& [slice, bins] : index_)
    count += frameCount(slice);
  return count;
}

std::size_t TextureStore::storedBytes() const {
  return frameCount() * frameFileBytes(layout_.resolution);
}

std::vector<SliceTexture> TextureStore::combine() const {
  std::vector<SliceTexture> out;
  const std::size_t texels = grid().texelCount();
  for (const SliceId& slice : slices()) {
    SliceTexture texture{slice, {}};
    for (const std::vector<Entry>& bin : index_.at(slice)) {
      std::vector<TextureFrame> frames;
      for (const Entry& e : bin)
        frames.push_back(readFrame(e.file, layout_.resolution));
      texture.bins.push_back(combineBinFrames(frames, texels));
    }
    out.push_back(std::move(texture));
  }
  return out;
}

}  // namespace slicecap::btf
