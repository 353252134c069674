// chooseRawStream: the RAW stream slicecap configures, shared by the libcamera backend and the
// hardware check's report; describeModes: the report's lines.
#include "slicecap/hal/camera_modes.hpp"

#include <gtest/gtest.h>

namespace slicecap::hal {
namespace {

// The camera module 3 (IMX708) on a Pi 4: its three sensor modes, as `rpicam-hello
// --list-cameras` prints them, in the sensor's CSI-2 packing and unpacked.
std::vector<OfferedFormat> imx708OnPi4() {
  const std::vector<std::pair<int, int>> modes{{1536, 864}, {2304, 1296}, {4608, 2592}};
  return {offeredFormat("SBGGR10", modes), offeredFormat("SRGGB10_CSI2P", modes),
          offeredFormat("YUYV", {{1280, 720}})};
}

TEST(ChooseRawStream, TakesTheProposedPackingAtTheModeThatBinsNearestTheRequest) {
  const RawStreamChoice choice = chooseRawStream(imx708OnPi4(), "SRGGB10_CSI2P", 1280, 720);
  EXPECT_EQ(choice.format, "SRGGB10_CSI2P");
  EXPECT_EQ(choice.modePx, (std::pair{2304, 1296}));
  EXPECT_EQ(choice.deliveredPx, (std::pair{1152, 648}));
  EXPECT_TRUE(choice.reason.empty());
}

TEST(ChooseRawStream, AnUndecodableProposalGivesWayToADecodableFormat) {
  std::vector<OfferedFormat> offered{offeredFormat("RGGB_PISP_COMP1", {{2304, 1296}}),
                                     offeredFormat("SRGGB12", {{2304, 1296}})};
  const RawStreamChoice choice = chooseRawStream(offered, "RGGB_PISP_COMP1", 1280, 720);
  EXPECT_EQ(choice.format, "SRGGB12");
}

TEST(ChooseRawStream, OnlyCompressedRawIsRefusedNamingTheFormat) {
  // The Pi 5's default: PiSP compressed RAW, which slicecap does not decode.
  std::vector<OfferedFormat> offered{offeredFormat("BGGR_PISP_COMP1", {{2304, 1296}}),
                                     offeredFormat("YUYV", {{1280, 720}})};
  EXPECT_FALSE(offered[0].decodable);
  EXPECT_TRUE(offered[0].raw);
  const RawStreamChoice choice = chooseRawStream(offered, "BGGR_PISP_COMP1", 1280, 720);
  EXPECT_TRUE(choice.format.empty());
  EXPECT_NE(choice.reason.find("BGGR_PISP_COMP1"), std::string::npos) << choice.reason;
}

TEST(ChooseRawStream, ACameraWithoutRawSaysSo) {
  const RawStreamChoice choice = chooseRawStream({offeredFormat("MJPG", {}), offeredFormat("YUYV", {})}, "", 640, 480);
  EXPECT_TRUE(choice.format.empty());
  EXPECT_NE(choice.reason.find("no RAW"), std::string::npos) << choice.reason;
}

TEST(ChooseRawStream, NoListedModesMeansTwiceTheRequest) {
  const RawStreamChoice choice = chooseRawStream({offeredFormat("SGRBG12_CSI2P", {})}, "", 640, 480);
  EXPECT_EQ(choice.modePx, (std::pair{1280, 960}));
  EXPECT_EQ(choice.deliveredPx, (std::pair{640, 480}));
}

TEST(DescribeModes, ListsEachFormatWithItsSizesAndWhetherRawIsDecoded) {
  CameraModes modes;
  modes.id = "libcamera: /base/soc/i2c0mux/i2c@1/imx708@1a";
  modes.formats = imx708OnPi4();
  modes.formats.push_back(offeredFormat("RGGB_PISP_COMP1", {{2304, 1296}}));
  modes.formats.push_back(offeredFormat("NV12", {}));
  const std::vector<std::string> lines = describeModes(modes);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], modes.id);
  EXPECT_EQ(lines[2], "  SRGGB10_CSI2P (RAW, decoded): 1536x864 2304x1296 4608x2592");
  EXPECT_EQ(lines[3], "  YUYV: 1280x720");
  EXPECT_EQ(lines[4], "  RGGB_PISP_COMP1 (RAW, not decoded): 2304x1296");
  EXPECT_EQ(lines[5], "  NV12: sizes as a range");
}

}  // namespace
}  // namespace slicecap::hal
