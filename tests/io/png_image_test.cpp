// PNG round trips at 8 and 16 bits, and errors for missing, foreign, truncated and corrupt files.
#include "slicecap/io/png_image.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>

#include "../support/memory_limit.hpp"
#include "../support/png_claiming_size.hpp"
#include "../support/png_palette.hpp"
#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

PngImage gradient(int channels, int bitDepth) {
  PngImage image{37, 23, channels, bitDepth, {}};
  image.samples.resize(std::size_t(37) * 23 * channels);
  const int top = bitDepth == 16 ? 65535 : 255;
  for (std::size_t i = 0; i < image.samples.size(); ++i)
    image.samples[i] = std::uint16_t((i * 7919) % (top + 1));
  return image;
}

std::string readError(const std::filesystem::path& path) {
  try {
    readPng(path);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(PngImage, RoundTripsEveryDepthAndChannelCount) {
  const auto dir = test::freshTempDir();
  for (int bitDepth : {8, 16}) {
    for (int channels = 1; channels <= 4; ++channels) {
      const PngImage image = gradient(channels, bitDepth);
      const auto path =
          dir / ("g" + std::to_string(bitDepth) + "_" + std::to_string(channels) + ".png");
      writePng(path, image);
      const PngImage back = readPng(path);
      EXPECT_EQ(back.width, 37);
      EXPECT_EQ(back.height, 23);
      EXPECT_EQ(back.channels, channels);
      EXPECT_EQ(back.bitDepth, bitDepth);
      EXPECT_EQ(back.samples, image.samples) << path;
    }
  }
}

TEST(PngImage, RejectsMissingForeignTruncatedAndCorruptFiles) {
  const auto dir = test::freshTempDir();
  EXPECT_NE(readError(dir / "none.png").find("none.png: cannot open"), std::string::npos);
  std::ofstream(dir / "text.png") << "hello, not an image";
  EXPECT_NE(readError(dir / "text.png").find("not a PNG"), std::string::npos);

  writePng(dir / "whole.png", gradient(3, 16));
  const auto size = std::filesystem::file_size(dir / "whole.png");
  std::filesystem::copy_file(dir / "whole.png", dir / "cut.png");
  std::filesystem::resize_file(dir / "cut.png", size / 2);
  EXPECT_NE(readError(dir / "cut.png").find("cut.png: corrupt or truncated PNG"),
            std::string::npos);

  std::filesystem::copy_file(dir / "whole.png", dir / "flipped.png");
  {
    std::fstream f(dir / "flipped.png", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(size / 2));
    const char garbage[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    f.write(garbage, sizeof garbage);
  }
  EXPECT_NE(readError(dir / "flipped.png").find("flipped.png"), std::string::npos);
}

TEST(PngImage, RefusesAHeaderClaimingMorePixelsThanTheFileCanHold) {
  // 100000 x 100000 ended in std::bad_alloc; 20000 x 20000 allocated 1.2 GB before libpng found
  // the data missing. Both are refused from the header, naming the file.
  const auto dir = test::freshTempDir();
  for (const auto& [width, height] :
       {std::pair<std::uint32_t, std::uint32_t>{100000, 100000}, {20000, 20000}, {70000, 1}}) {
    SCOPED_TRACE(std::to_string(width) + " x " + std::to_string(height));
    const auto path = test::writePngClaimingSize(dir / "bomb.png", width, height);
    const std::string message = readError(path);
    EXPECT_NE(message.find("bomb.png: corrupt PNG header"), std::string::npos) << message;
    EXPECT_NE(message.find(std::to_string(width) + " x " + std::to_string(height)),
              std::string::npos)
        << message;
  }
  // A real image that compresses very well is not mistaken for one.
  PngImage black{2000, 1000, 1, 8, std::vector<std::uint16_t>(2000 * 1000, 0)};
  writePng(dir / "black.png", black);
  EXPECT_LT(std::filesystem::file_size(dir / "black.png"), 20000u);
  const PngImage back = readPng(dir / "black.png");
  EXPECT_EQ(back.width, 2000);
  EXPECT_EQ(back.samples, black.samples);
}

// The check above bounds the stored bits; libpng expands a 1-bit palette image 24 (RGB) or 32
// (RGBA) times, so a 50 kB file of 20000 x 20000 palette indices allocated 1.6 GB of rows (and
// would have allocated 3.2 GB of samples) before libpng found its data damaged, and a valid
// one ended in std::bad_alloc where memory is short. Seen while reviewing the reader for
// tests/fuzz/png_fuzz, which reproduces it (a 49 kB image: out-of-memory, malloc of 2.4 GB).
TEST(PngImage, ExpandedPixelsAreAllocatedOnlyForDataThatIsThere) {
#ifdef SLICECAP_TESTS_UNDER_EMULATOR
  GTEST_SKIP() << "under qemu-user the child's address-space limit also binds the emulator; "
                  "this runs natively";
#endif
  const auto dir = test::freshTempDir();
  const auto damaged = test::writeBlackPalettePng(dir / "damaged.png", 20000, 20000, true);
  {
    // A byte in the middle of the compressed pixels changed, so that their chunk's CRC fails.
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    const auto middle = std::streamoff(std::filesystem::file_size(damaged) / 2);
    f.seekg(middle);
    const char byte = static_cast<char>(f.get() ^ 0xff);
    f.seekp(middle);
    f.put(byte);
  }
  const auto valid = test::writeBlackPalettePng(dir / "valid.png", 20000, 20000, false);
  ASSERT_LT(std::filesystem::file_size(valid), 60000u);
  // In a child that cannot allocate 1 GB: the damaged file is refused as such, the valid one as
  // too large; neither may end in std::bad_alloc.
  const auto outcome = [](const std::filesystem::path& path, const std::string& expected) {
    return test::exitCodeWithMemoryLimit(std::size_t(1) << 30, [&] {
      try {
        readPng(path);
      } catch (const IoError& e) {
        return std::string(e.what()).find(path.filename().string() + ": " + expected) !=
                       std::string::npos
                   ? 0
                   : 1;
      } catch (const std::bad_alloc&) {
        return 2;
      }
      return 3;
    });
  };
  EXPECT_EQ(outcome(damaged, "corrupt or truncated PNG"), 0)
      << "1: another error, 2: std::bad_alloc, 3: no error";
  EXPECT_EQ(outcome(valid, "20000 x 20000 pixels take"), 0)
      << "1: another error, 2: std::bad_alloc, 3: no error";

  // A valid palette image that compresses very well reads as before.
  const auto small = test::writeBlackPalettePng(dir / "small.png", 2000, 1000, true);
  ASSERT_LT(std::filesystem::file_size(small), 2000u);
  const PngImage back = readPng(small);
  EXPECT_EQ(back.width, 2000);
  EXPECT_EQ(back.height, 1000);
  EXPECT_EQ(back.channels, 4);
  EXPECT_EQ(back.samples, std::vector<std::uint16_t>(2000 * 1000 * 4, 0));
}

TEST(PngImage, RefusesToWriteInconsistentImages) {
  const auto dir = test::freshTempDir();
  PngImage bad = gradient(3, 8);
  bad.samples.pop_back();
  EXPECT_THROW(writePng(dir / "bad.png", bad), IoError);
  PngImage tooBright = gradient(1, 8);
  tooBright.samples[5] = 256;
  EXPECT_THROW(writePng(dir / "bright.png", tooBright), IoError);
}

}  // namespace
}  // namespace slicecap::io
