// Writing and reading the BTF directory: UTIA-named EXRs, the average, previews, the manifest.
#include "slicecap/btf/btf_files.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "slicecap/core/version.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"

namespace slicecap::btf {
namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};
constexpr int kPreviewMinSide = 256;  // previews of small textures are enlarged (nearest texel)

std::string threeDigits(double degrees) {
  char text[8];
  std::snprintf(text, sizeof text, "%03d", static_cast<int>(std::lround(degrees)) % 1000);
  return text;
}

Imf::FrameBuffer halfBuffer(const std::uint16_t* base, int resolution) {
  const std::size_t xStride = 3 * sizeof(std::uint16_t);
  Imf::FrameBuffer frame;
  for (int c = 0; c < 3; ++c)
    frame.insert(kChannels[c],
                 Imf::Slice(Imf::HALF, const_cast<char*>(reinterpret_cast<const char*>(base + c)),
                            xStride, xStride * std::size_t(resolution)));
  return frame;
}

void writeImage(const std::filesystem::path& path, const BtfTexture& texture, int light, int view) {
  const int n = texture.resolution();
  Imf::Header header(n, n);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : kChannels)
    header.channels().insert(name, Imf::Channel(Imf::HALF));
  header.insert("slicecap:quantity", Imf::StringAttribute("brdf"));
  header.insert("slicecap:layout", Imf::StringAttribute("btf-utia"));
  // Encoded in memory (OpenEXR's own file stream flushes its last bytes in its destructor, where
  // a failed write goes unreported), then written through a temporary renamed onto the image: an
  // interrupted or failed run never leaves a truncated image in place of a whole one.
  Imf::StdOSStream encoded;
  try {
    Imf::OutputFile file(encoded, header);  // destroyed (the offsets written) before str()
    file.setFrameBuffer(halfBuffer(texture.image(light, view), n));
    file.writePixels(n);
  } catch (const std::exception& e) {
    throw io::IoError(path.string() + ": cannot write EXR: " + e.what());
  }
  const std::string bytes = encoded.str();
  io::writeStreamReplacing(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

// Runs body(k) for k in [0, count) on `threads` threads; the first exception is rethrown.
template <typename Body>
void parallelFor(int count, int threads, Body body) {
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex mutex;
  {
    std::vector<std::jthread> pool;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&] {
        for (int k = next++; k < count; k = next++) {
          try {
            body(k);
          } catch (...) {
            const std::lock_guard lock(mutex);
            if (!failure) failure = std::current_exception();
            next = count;
          }
        }
      });
  }
  if (failure) std::rethrow_exception(failure);
}

// 8-bit sRGB previews of BRDF x cos(theta_i) from straight above, one exposure for all: the
// 99th percentile of every preview's values maps to 90 % of full scale.
void writePreviews(const std::filesystem::path& directory, const BtfTexture& texture) {
  std::filesystem::create_directories(directory);
  const int n = texture.resolution();
  const int view = bonn::indexOf({0.0, 0.0});
  std::vector<Direction> lights = previewLights();
  std::vector<float> all;
  for (const Direction& light : lights)
    for (std::size_t t = 0; t < texture.texelCount(); ++t)
      for (int c = 0; c < 3; ++c)
        all.push_back(texture.value(bonn::indexOf(light), view, t, c) *
                      static_cast<float>(std::cos(light.thetaDeg * M_PI / 180.0)));
  std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(all.size() * 99 / 100), all.end());
  const double top = std::max(1e-9, double(all[all.size() * 99 / 100]));
  const int zoom = std::max(1, (kPreviewMinSide + n - 1) / n);
  for (const Direction& light : lights) {
    const double cosine = std::cos(light.thetaDeg * M_PI / 180.0);
    Image image{n * zoom, n * zoom, 3, 8,
                std::vector<std::uint16_t>(std::size_t(n * zoom) * n * zoom * 3)};
    for (int y = 0; y < n * zoom; ++y)
      for (int x = 0; x < n * zoom; ++x)
        for (int c = 0; c < 3; ++c) {
          const double v = texture.value(bonn::indexOf(light), view,
                                         std::size_t(y / zoom) * n + std::size_t(x / zoom), c) *
                           cosine * 0.9 / top;
          image.at(x, y, c) = static_cast<std::uint16_t>(
              std::lround(255.0 * eval::srgbEncode(std::clamp(v, 0.0, 1.0))));
        }
    io::writePng(directory / ("preview_" + utiaName(light, {0.0, 0.0}) + ".png"), image);
  }
}

}  // namespace

std::string utiaName(const Direction& light, const Direction& view) {
  return "tl" + threeDigits(light.thetaDeg) + "_pl" + threeDigits(light.phiDeg) + "_tv" +
         threeDigits(view.thetaDeg) + "_pv" + threeDigits(view.phiDeg);
}

std::filesystem::path imagePath(int light, int view) {
  const Direction v = bonn::direction(view);
  return std::filesystem::path("tv" + threeDigits(v.thetaDeg) + "_pv" + threeDigits(v.phiDeg)) /
         (utiaName(bonn::direction(light), v) + ".exr");
}

std::vector<Direction> previewLights() {
  return {{30.0, 0.0}, {30.0, 90.0}, {30.0, 180.0}, {30.0, 270.0},
          {60.0, 0.0}, {60.0, 90.0}, {60.0, 180.0}, {60.0, 270.0}};
}

void writeBtfDirectory(const std::filesystem::path& directory, const BtfTexture& texture,
                       const Abrdf& average, const BtfDescription& description,
                       const io::ExrAttributes& averageAttributes, int threads) {
  std::error_code error;
  for (int view = 0; view < Abrdf::kDirections; ++view) {
    std::filesystem::create_directories(directory / imagePath(0, view).parent_path(), error);
    if (error)
      throw io::IoError((directory / imagePath(0, view).parent_path()).string() + ": " +
                        error.message());
  }
  const int pool = std::max(1, threads > 0 ? threads : int(std::thread::hardware_concurrency()));
  const int count = Abrdf::kDirections * Abrdf::kDirections;
  parallelFor(count, pool, [&](int k) {
    const int light = k / Abrdf::kDirections, view = k % Abrdf::kDirections;
    writeImage(directory / imagePath(light, view), texture, light, view);
  });
  io::writeAbrdfExr(directory / "average.exr", average, averageAttributes);
  writePreviews(directory / "preview", texture);
  const nlohmann::json manifest = {
      {"format", "slicecap-btf"},
      {"version", 1},
      {"created_by", std::string("slicecap ") + kVersion},
      {"resolution", texture.resolution()},
      {"window_mm",
       {description.windowMm.xMinMm, description.windowMm.yMinMm, description.windowMm.xMaxMm,
        description.windowMm.yMaxMm}},
      {"texel_mm", description.windowMm.widthMm() / texture.resolution()},
      {"quantity", "brdf"},
      {"unit", "1/sr"},
      {"colour", "linear RGB, sRGB primaries"},
      {"sample_type", "half"},
      {"directions", "bonn81"},
      {"images", count},
      {"image_name", "tvTTT_pvPPP/tlTTT_plPPP_tvTTT_pvPPP.exr"},
      {"row_0", "top of the window (largest y); column 0 its left edge (smallest x)"},
      {"method", description.method},
      {"average", "average.exr"},
      {"average_method", description.averageMethod},
      {"source", description.source},
      {"failed_texels", description.failedTexels},
      {"previews", "preview/"}};
  io::writeStreamReplacing(directory / kBtfManifest,
                           [&](std::ostream& out) { out << manifest.dump(1) << "\n"; });
}

namespace {

// `field` of `manifest` must be the string `expected`.
void requireString(const nlohmann::json& manifest, const std::filesystem::path& manifestPath,
                   const char* field, const char* expected) {
  if (!manifest.contains(field) || !manifest.at(field).is_string() ||
      manifest.at(field).get<std::string>() != expected)
    throw io::IoError(manifestPath.string() + ": field '" + field + "' is not \"" + expected + "\"");
}

// The image at `path`, of data window `window`, is resolution x resolution, as btf.json says.
void requireSize(const Imath::Box2i& window, const std::filesystem::path& path, int resolution) {
  if (window.max.x - window.min.x + 1 != resolution || window.max.y - window.min.y + 1 != resolution)
    throw io::IoError(path.string() + ": not " + std::to_string(resolution) + " x " +
                      std::to_string(resolution) + " as btf.json says");
}

// The image at `path` is resolution x resolution: checked before 6561 of them are allocated, so
// that a manifest claiming a larger texture is named, not an allocation failure.
void requireImageSize(const std::filesystem::path& path, int resolution) {
  try {
    Imf::InputFile file(path.c_str());
    requireSize(file.header().dataWindow(), path, resolution);
  } catch (const io::IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw io::IoError(path.string() + ": " + e.what());
  }
}

}  // namespace

BtfManifest readBtfManifest(const std::filesystem::path& directory) {
  const std::filesystem::path manifestPath = directory / kBtfManifest;
  std::ifstream in(manifestPath);
  if (!in) throw io::IoError(manifestPath.string() + ": cannot open (not a BTF directory?)");
  BtfManifest out;
  try {
    const nlohmann::json manifest = nlohmann::json::parse(in);
    if (!manifest.is_object() || manifest.value("format", "") != "slicecap-btf")
      throw io::IoError(manifestPath.string() + ": field 'format' is not \"slicecap-btf\"");
    // Checked before get<int>(): of 1e300 it is undefined behaviour, of 2.5 quietly 2.
    const nlohmann::json& value = manifest.at("resolution");
    if (!value.is_number_integer() || value < 1 || value > 1024)
      throw io::IoError(manifestPath.string() + ": field 'resolution' is not a whole number of " +
                        "texels in 1..1024");
    out.resolution = value.get<int>();
    const auto isFinite = [](const nlohmann::json& v) {
      return v.is_number() && std::isfinite(v.get<double>());
    };
    const nlohmann::json* window = manifest.contains("window_mm") ? &manifest.at("window_mm") : nullptr;
    if (window == nullptr || !window->is_array() || window->size() != 4 ||
        !std::all_of(window->begin(), window->end(), isFinite) ||
        !((*window)[0].get<double>() < (*window)[2].get<double>() &&
          (*window)[1].get<double>() < (*window)[3].get<double>()))
      throw io::IoError(manifestPath.string() +
                        ": field 'window_mm' is not [x_min, y_min, x_max, y_max] (mm, min < max)");
    out.windowMm = {(*window)[0].get<double>(), (*window)[1].get<double>(),
                    (*window)[2].get<double>(), (*window)[3].get<double>()};
    if (!manifest.contains("version") || !manifest.at("version").is_number_integer() ||
        manifest.at("version") != 1)
      throw io::IoError(manifestPath.string() + ": field 'version' is not 1");
    requireString(manifest, manifestPath, "quantity", "brdf");
    requireString(manifest, manifestPath, "unit", "1/sr");
  } catch (const nlohmann::json::exception& e) {
    throw io::IoError(manifestPath.string() + ": " + e.what());
  }
  return out;
}

BtfTexture readBtfDirectory(const std::filesystem::path& directory) {
  const int resolution = readBtfManifest(directory).resolution;
  requireImageSize(directory / imagePath(0, 0), resolution);
  BtfTexture texture(resolution);
  for (int light = 0; light < Abrdf::kDirections; ++light) {
    for (int view = 0; view < Abrdf::kDirections; ++view) {
      const std::filesystem::path path = directory / imagePath(light, view);
      try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        requireSize(window, path, resolution);
        for (const char* name : kChannels)
          if (!file.header().channels().findChannel(name))
            throw io::IoError(path.string() + ": no channel " + name);
        file.setFrameBuffer(halfBuffer(texture.image(light, view), resolution));
        file.readPixels(window.min.y, window.max.y);
      } catch (const io::IoError&) {
        throw;
      } catch (const std::exception& e) {
        throw io::IoError(path.string() + ": " + e.what());
      }
    }
  }
  return texture;
}

}  // namespace slicecap::btf
