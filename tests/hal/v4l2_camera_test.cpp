// The V4L2 source's errors without a camera: a missing node and a node that is not a V4L2 device
// are refused with the path in the message.
#include "slicecap/hal/v4l2_camera.hpp"
#include "slicecap/hal/v4l2_timestamp.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>

namespace slicecap::hal {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

TEST(V4l2Camera, AMissingDeviceIsNamedInTheError) {
  EXPECT_THAT([] { V4l2Camera camera("/dev/slicecap-no-such-video"); },
              ::testing::ThrowsMessage<CameraError>(AllOf(
                  HasSubstr("/dev/slicecap-no-such-video"), HasSubstr("cannot open the camera"))));
}

TEST(V4l2Camera, ADeviceThatIsNotAV4l2NodeIsRefused) {
  EXPECT_THAT([] { V4l2Camera camera("/dev/null"); },
              ::testing::ThrowsMessage<CameraError>(
                  AllOf(HasSubstr("/dev/null"), HasSubstr("not a V4L2 device"))));
}

// The colour fields as the V4L2 documentation defines them ("Colorspaces", "Defining
// Colorspaces in V4L2"): a DEFAULT encoding or quantization is the colorspace's own.
TEST(V4l2Camera, AYuvStreamIsDecodedByTheColourSpaceTheDriverReports) {
  using E = YuvEncoding;
  // uvcvideo's default (no colour matching descriptor): sRGB, so BT.601 limited.
  EXPECT_EQ(yuvEncodingOfV4l2(V4L2_COLORSPACE_SRGB, 0, 0, nullptr),
            (E{YcbcrMatrix::Rec601, YuvRange::Limited}));
  EXPECT_EQ(yuvEncodingOfV4l2(V4L2_COLORSPACE_JPEG, 0, 0, nullptr),
            (E{YcbcrMatrix::Rec601, YuvRange::Full}));
  EXPECT_EQ(yuvEncodingOfV4l2(V4L2_COLORSPACE_REC709, 0, 0, nullptr),
            (E{YcbcrMatrix::Rec709, YuvRange::Limited}));
  EXPECT_EQ(yuvEncodingOfV4l2(V4L2_COLORSPACE_REC709, V4L2_YCBCR_ENC_709,
                              V4L2_QUANTIZATION_FULL_RANGE, nullptr),
            (E{YcbcrMatrix::Rec709, YuvRange::Full}));
  EXPECT_EQ(yuvEncodingOfV4l2(V4L2_COLORSPACE_BT2020, 0, 0, nullptr),
            (E{YcbcrMatrix::Rec2020, YuvRange::Limited}));
  // Said, not guessed: no colorspace at all, or an encoding the decoder does not have.
  std::string why;
  EXPECT_FALSE(yuvEncodingOfV4l2(V4L2_COLORSPACE_DEFAULT, 0, 0, &why));
  EXPECT_THAT(why, HasSubstr("no colorspace"));
  EXPECT_FALSE(yuvEncodingOfV4l2(V4L2_COLORSPACE_SMPTE240M, 0, 0, &why));
  EXPECT_THAT(why, HasSubstr("encoding"));
}

// The buffer flags as the kernel's documentation defines them (struct v4l2_buffer): which clock
// the timestamp is on, and which moment of the frame it marks.
TEST(V4l2Timestamp, StartOfExposureIsTheTimestampItself) {
  const std::uint32_t soe = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
  EXPECT_EQ(v4l2ExposureStartUs(soe, 5'000'000, 10'000.0, std::nullopt), 5'000'000);
  // Exposure and readout do not matter when the timestamp marks the start.
  EXPECT_EQ(v4l2ExposureStartUs(soe, 5'000'000, 0.0, 20'000.0), 5'000'000);
}

TEST(V4l2Timestamp, EndOfFrameSubtractsReadoutAndExposureWhenBothAreKnown) {
  const std::uint32_t eof = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF;
  EXPECT_EQ(v4l2ExposureStartUs(eof, 5'000'000, 10'000.0, 28'800.0), 5'000'000 - 38'800);
  EXPECT_EQ(v4l2ExposureStartUs(eof, 5'000'000, 10'000.0, std::nullopt), std::nullopt);
  EXPECT_EQ(v4l2ExposureStartUs(eof, 5'000'000, 0.0, 28'800.0), std::nullopt);  // auto exposure
}

TEST(V4l2Timestamp, OnlyMonotonicTimestampsShareTheLedsClock) {
  for (std::uint32_t clock : {std::uint32_t(V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN),
                              std::uint32_t(V4L2_BUF_FLAG_TIMESTAMP_COPY)})
    EXPECT_EQ(v4l2ExposureStartUs(clock | V4L2_BUF_FLAG_TSTAMP_SRC_SOE, 5'000'000, 10'000.0, 1.0),
              std::nullopt);
  // Other flags of the buffer (a keyframe, done) change nothing.
  EXPECT_EQ(v4l2ExposureStartUs(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE |
                                    V4L2_BUF_FLAG_DONE | V4L2_BUF_FLAG_KEYFRAME,
                                7, 1.0, std::nullopt),
            7);
  // A source value the flags did not define yet: unknown, not guessed.
  EXPECT_EQ(v4l2ExposureStartUs(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | 0x20000, 7, 1.0, 1.0),
            std::nullopt);
}

}  // namespace
}  // namespace slicecap::hal
