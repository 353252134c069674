// libpng reading and writing with errors turned into IoError (libpng reports through longjmp).
#include "slicecap/io/png_image.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <new>
#include <string>

#include "input_file.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// libpng's error callback: keep the message; the caller longjmps back to its setjmp.
void onError(png_structp png, png_const_charp message) {
  auto* text = static_cast<std::string*>(png_get_error_ptr(png));
  if (text) *text = message;
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

// libpng's write callback: appends the encoded bytes to the std::string it was given. An
// allocation failure becomes a libpng error, raised outside the catch (png_error longjmps).
void appendToString(png_structp png, png_bytep data, png_size_t length) {
  bool appended = true;
  try {
    static_cast<std::string*>(png_get_io_ptr(png))
        ->append(reinterpret_cast<const char*>(data), length);
  } catch (const std::exception&) {
    appended = false;
  }
  if (!appended) png_error(png, "out of memory");
}
// Without a flush callback libpng would fflush its io pointer as a FILE*.
void flushNothing(png_structp) {}

// Runs `libpngCalls` under libpng's error trap and returns false if libpng reported an error.
// Only libpng calls may run inside: a longjmp out of them must not skip any C++ destructor, so
// every buffer is made before and outside this call.
template <typename Calls>
bool trapLibpngErrors(png_structp png, Calls&& libpngCalls) {
  if (setjmp(png_jmpbuf(png))) return false;
  libpngCalls();
  return true;
}

// Decodes every row of the PNG at `path` into one scratch row and throws them away: whether
// the pixel data the header claims is really there, found without allocating for it. False, with
// libpng's message, when it is not.
bool pixelDataIsWhole(const std::filesystem::path& path, std::string* message) {
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) {
    *message = "cannot open it again";
    return false;
  }
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, message, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    *message = "out of memory";
    return false;
  }
  int passes = 1;
  png_uint_32 height = 0;
  const bool headerRead = trapLibpngErrors(png, [&] {
    png_init_io(png, file.get());
    png_read_info(png, info);
    passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    height = png_get_image_height(png, info);
  });
  // One stored row: at most 65535 pixels of 64 bits, as the caller has checked.
  std::vector<png_byte> row(headerRead ? png_get_rowbytes(png, info) : 0);
  const bool whole = headerRead && trapLibpngErrors(png, [&] {
                       for (int pass = 0; pass < passes; ++pass) {
                         for (png_uint_32 y = 0; y < height; ++y)
                           png_read_row(png, row.data(), nullptr);
                       }
                       png_read_end(png, nullptr);
                     });
  png_destroy_read_struct(&png, &info, nullptr);
  return whole;
}

// libpng's read and info structs for one file, destroyed with this object; `message` keeps
// libpng's last error (onError writes it). Neither copied nor moved: libpng holds &message.
class PngReadState {
 public:
  explicit PngReadState(const std::filesystem::path& path) {
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &message, onError, onWarning);
    info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
      png_destroy_read_struct(&png, nullptr, nullptr);
      throw IoError(path.string() + ": out of memory reading PNG");
    }
  }
  ~PngReadState() { png_destroy_read_struct(&png, &info, nullptr); }
  PngReadState(const PngReadState&) = delete;
  PngReadState& operator=(const PngReadState&) = delete;

  png_structp png = nullptr;
  png_infop info = nullptr;
  std::string message;
};

// Deflate cannot expand its input more than 1032:1; the headroom covers a tiny file's chunks.
constexpr std::uint64_t kDeflateMaxRatio = 1032, kHeadroomBytes = 4096;

// Opens `path` and checks the PNG signature; the returned file is positioned after it.
File openPngFile(const std::filesystem::path& path) {
  refuseDirectory(path, "a PNG");
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) throw IoError(path.string() + ": cannot open PNG");
  png_byte signature[8];
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
    throw IoError(path.string() + ": not a PNG file");
  }
  return file;
}

// What the header claims, as stored (before palettes and low bit depths are expanded).
struct StoredPngHeader {
  png_uint_32 claimedWidth = 0, claimedHeight = 0;
  int storedBitsPerPixel = 0;
};

StoredPngHeader readStoredHeader(PngReadState& read, std::FILE* file,
                                 const std::filesystem::path& path) {
  StoredPngHeader header;
  const bool headerRead = trapLibpngErrors(read.png, [&] {
    png_init_io(read.png, file);
    png_set_sig_bytes(read.png, 8);
    png_read_info(read.png, read.info);
    header.claimedWidth = png_get_image_width(read.png, read.info);
    header.claimedHeight = png_get_image_height(read.png, read.info);
    header.storedBitsPerPixel =
        png_get_channels(read.png, read.info) * png_get_bit_depth(read.png, read.info);
  });
  if (!headerRead) throw IoError(path.string() + ": corrupt PNG header (" + read.message + ")");
  return header;
}

// A header may claim any size; the pixels are allocated from it before a byte of them is read.
// Deflate cannot expand its input more than 1032:1, so a claim the file's size cannot hold is
// a corrupt (or hostile) file: refused before a 100-byte file makes us allocate gigabytes.
// Returns the file's size in bytes.
std::uintmax_t refuseClaimsTheFileCannotHold(const std::filesystem::path& path,
                                             const StoredPngHeader& header) {
  const png_uint_32 claimedWidth = header.claimedWidth, claimedHeight = header.claimedHeight;
  if (claimedWidth > kMaxPngSidePx || claimedHeight > kMaxPngSidePx) {
    throw IoError(path.string() + ": corrupt PNG header (claims " + std::to_string(claimedWidth) +
                  " x " + std::to_string(claimedHeight) + " pixels; at most " +
                  std::to_string(kMaxPngSidePx) + " a side are read)");
  }
  std::error_code sizeError;
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, sizeError);
  const std::uint64_t storedRowBytes =
      (std::uint64_t(claimedWidth) * header.storedBitsPerPixel + 7) / 8;
  const std::uint64_t inflatedBytes = (storedRowBytes + 1) * claimedHeight;  // + filter bytes
  if (sizeError || inflatedBytes > kDeflateMaxRatio * fileBytes + kHeadroomBytes) {
    throw IoError(path.string() + ": corrupt PNG header (claims " + std::to_string(claimedWidth) +
                  " x " + std::to_string(claimedHeight) + " pixels, " +
                  std::to_string(inflatedBytes) + " bytes, more than a file of " +
                  std::to_string(fileBytes) + " bytes can hold)");
  }
  return fileBytes;
}

// Expands palettes, low-bit grays and transparency to 8-bit channels; returns the decoded shape
// (no samples yet).
PngImage setExpandingTransforms(PngReadState& read, const std::filesystem::path& path) {
  const bool transformsSet = trapLibpngErrors(read.png, [&] {
    const int colourType = png_get_color_type(read.png, read.info);
    const int depth = png_get_bit_depth(read.png, read.info);
    if (colourType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(read.png);
    if (colourType == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(read.png);
    if (png_get_valid(read.png, read.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(read.png);
    png_read_update_info(read.png, read.info);
  });
  if (!transformsSet) throw IoError(path.string() + ": corrupt PNG header (" + read.message + ")");
  PngImage image;
  image.width = static_cast<int>(png_get_image_width(read.png, read.info));
  image.height = static_cast<int>(png_get_image_height(read.png, read.info));
  image.channels = png_get_channels(read.png, read.info);
  image.bitDepth = png_get_bit_depth(read.png, read.info);
  return image;
}

// What reading takes: libpng's rows, expanded (a palette or 1-bit image to 8-bit RGB(A): up to
// 32 times the stored bits), and the 16-bit samples. The check on the claims bounds the stored
// bits only, so a 70 kB file of 1-bit palette indices could make this 7 GB. Unless the file could
// hold it even unexpanded, the pixel data must be there, decoded once without keeping it,
// before anything is allocated for it; a valid image is read as before, only slower.
void refuseMissingPixelData(const std::filesystem::path& path, const PngImage& shape,
                            std::uint64_t decodedBytes, std::uintmax_t fileBytes) {
  if (decodedBytes > 3 * (kDeflateMaxRatio * fileBytes + kHeadroomBytes)) {
    std::string whyNot;
    if (!pixelDataIsWhole(path, &whyNot)) {
      throw IoError(path.string() + ": corrupt or truncated PNG (" + whyNot +
                    "; its header claims " + std::to_string(shape.width) + " x " +
                    std::to_string(shape.height) + " pixels)");
    }
  }
}

// Copies libpng's decoded rows into `image.samples` (already sized).
void copyRowsToSamples(const std::vector<png_bytep>& rows, PngImage& image) {
  for (int y = 0; y < image.height; ++y) {
    const png_byte* row = rows[y];
    std::uint16_t* out = image.samples.data() + std::size_t(y) * image.width * image.channels;
    const std::size_t count = std::size_t(image.width) * image.channels;
    for (std::size_t i = 0; i < count; ++i) {
      // PNG stores 16-bit samples big-endian.
      out[i] = image.bitDepth == 16 ? std::uint16_t((row[2 * i] << 8) | row[2 * i + 1]) : row[i];
    }
  }
}

// Allocates for and reads the pixels of `image` (its shape set), then fills its samples.
void readPixels(PngReadState& read, const std::filesystem::path& path, PngImage& image,
                std::uint64_t decodedBytes) {
  const std::size_t rowBytes = png_get_rowbytes(read.png, read.info);
  const std::size_t sampleCount = std::size_t(image.width) * image.height * image.channels;
  // A valid image may still need more memory than there is: an error naming the file, not
  // std::bad_alloc.
  const auto tooLarge = [&] {
    return IoError(path.string() + ": " + std::to_string(image.width) + " x " +
                   std::to_string(image.height) + " pixels take " +
                   std::to_string(decodedBytes / 1000000) +
                   " MB to read, more memory than can be allocated");
  };
  std::vector<png_byte> pixels;
  std::vector<png_bytep> rows;
  try {
    pixels.resize(rowBytes * image.height);
    rows.resize(image.height);
    image.samples.resize(sampleCount);
  } catch (const std::bad_alloc&) {
    throw tooLarge();
  }
  for (int y = 0; y < image.height; ++y)
    rows[y] = pixels.data() + rowBytes * y;
  const bool pixelsRead = trapLibpngErrors(read.png, [&] {
    png_read_image(read.png, rows.data());
    png_read_end(read.png, nullptr);
  });
  if (!pixelsRead)
    throw IoError(path.string() + ": corrupt or truncated PNG (" + read.message + ")");
  copyRowsToSamples(rows, image);
}

}  // namespace

PngImage readPng(const std::filesystem::path& path) {
  const File file = openPngFile(path);
  PngReadState read(path);
  const StoredPngHeader header = readStoredHeader(read, file.get(), path);
  const std::uintmax_t fileBytes = refuseClaimsTheFileCannotHold(path, header);
  PngImage image = setExpandingTransforms(read, path);
  const std::size_t rowBytes = png_get_rowbytes(read.png, read.info);
  const std::size_t sampleCount = std::size_t(image.width) * image.height * image.channels;
  const std::uint64_t decodedBytes = std::uint64_t(rowBytes) * image.height + 2 * sampleCount;
  refuseMissingPixelData(path, image, decodedBytes, fileBytes);
  readPixels(read, path, image, decodedBytes);
  return image;
}

void writePng(const std::filesystem::path& path, const PngImage& image, double pixelsPerMetre) {
  if (!image.isValid())
    throw IoError(path.string() + ": cannot write an image of inconsistent shape");
  if (image.bitDepth == 8) {
    for (std::uint16_t s : image.samples) {
      if (s > 255) throw IoError(path.string() + ": sample above 255 in an 8-bit image");
    }
  }
  const int colourTypes[] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                             PNG_COLOR_TYPE_RGB_ALPHA};
  const std::size_t rowSamples = std::size_t(image.width) * image.channels;
  const std::size_t bytesPerSample = image.bitDepth / 8;
  std::vector<png_byte> pixels(rowSamples * bytesPerSample * image.height);
  for (std::size_t i = 0; i < image.samples.size(); ++i) {
    if (bytesPerSample == 2) {  // PNG is big-endian
      pixels[2 * i] = png_byte(image.samples[i] >> 8);
      pixels[2 * i + 1] = png_byte(image.samples[i] & 0xff);
    } else {
      pixels[i] = png_byte(image.samples[i]);
    }
  }
  std::vector<png_bytep> rows(image.height);
  for (int y = 0; y < image.height; ++y)
    rows[y] = pixels.data() + rowSamples * bytesPerSample * y;

  // Encoded in memory, then written through a temporary: a failed write leaves any old file.
  std::string encoded;
  encoded.reserve(pixels.size() / 2 + 1024);
  std::string message;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw IoError(path.string() + ": out of memory writing PNG");
  }
  const bool written = trapLibpngErrors(png, [&] {
    png_set_write_fn(png, &encoded, appendToString, flushNothing);
    png_set_IHDR(png, info, image.width, image.height, image.bitDepth, colourTypes[image.channels],
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (pixelsPerMetre > 0.0) {
      const auto density = static_cast<png_uint_32>(pixelsPerMetre + 0.5);
      png_set_pHYs(png, info, density, density, PNG_RESOLUTION_METER);
    }
    // Speed over size: frames are written while capturing. The adaptive filter choice tries all
    // five filters on every row; Sub alone at level 1 writes a noisy 720p frame 2.5 x faster for
    // 7 % more bytes (bench/sim_render_bench BM_WritePngFrame).
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
  });
  png_destroy_write_struct(&png, &info);
  if (!written) throw IoError(path.string() + ": cannot write PNG (" + message + ")");
  writeStreamReplacing(path, [&](std::ostream& out) {
    out.write(encoded.data(), static_cast<std::streamsize>(encoded.size()));
  });
}

}  // namespace slicecap::io
