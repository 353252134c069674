// chooseRawStream and negotiateRawStream: the RAW stream slicecap configures, shared by the
// libcamera backend and the hardware check's report, checked against validators that behave as
// a Pi 4's and a Pi 5's libcamera; describeModes: the report's lines.
#include "slicecap/hal/camera_modes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>

#include "slicecap/hal/bayer_frame.hpp"

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

// What libcamera's Raspberry Pi pipelines' validate() does to a RAW stream (the Raspberry Pi
// fork, src/libcamera/pipeline/rpi/common/pipeline_base.cpp RPiCameraConfiguration::validate and
// the platformValidate of pisp/pisp.cpp and vc4/vc4.cpp, the same from v0.1.0+rpt20231122 to
// v0.7.1+rpt20260429): the CFA order becomes the sensor's (no flips), the size the sensor mode's;
// a Pi 4 (vc4) applies the mode's bit depth and keeps CSI-2 packed or unpacked; a Pi 5 (PiSP)
// cannot write CSI-2 packed or anything but 16 bits from its frontend: a packed request becomes
// the compressed <ORDER>_PISP_COMP1, an unpacked one 16-bit words (S<ORDER>16).
struct PiCamera {
  enum class Isp { Vc4, PiSp };
  explicit PiCamera(Isp platform, BayerOrder sensorOrder = BayerOrder::Rggb, int sensorBits = 10)
      : isp(platform), order(sensorOrder), bitDepth(sensorBits) {}
  Isp isp;
  BayerOrder order;  // the sensor's, without flips
  int bitDepth;      // of every sensor mode
  std::vector<std::pair<int, int>> modesPx{{1536, 864}, {2304, 1296}, {4608, 2592}};
  std::vector<std::string> asked;  // every request validated, in order

  RawValidation validate(const std::string& format, std::pair<int, int> modePx) {
    asked.push_back(format);
    const bool compressed = format == "RGGB_PISP_COMP1";
    std::optional<BayerFormat> bayer = bayerFormatFromLibcameraName(format);
    if (compressed) bayer = BayerFormat{BayerOrder::Rggb, 16, BayerPacking::Unpacked16};
    if (!bayer) return {true, format, modePx};  // not a Bayer format it knows
    const bool known = std::find(modesPx.begin(), modesPx.end(), modePx) != modesPx.end();
    const std::pair<int, int> sensorMode = known ? modePx : modesPx.back();
    BayerFormat granted{order, bayer->bitDepth, bayer->packing};
    if (isp == Isp::Vc4) {
      granted.bitDepth = bitDepth;
      return {false, bayerFormatName(granted), sensorMode};
    }
    if (compressed || granted.packing == BayerPacking::Csi2Packed)
      return {false, "RGGB_PISP_COMP1", sensorMode};  // the sensor here is RGGB
    granted.bitDepth = 16;
    return {false, bayerFormatName(granted), sensorMode};
  }
  RawValidator validator() {
    return [this](const std::string& format, std::pair<int, int> modePx) {
      return validate(format, modePx);
    };
  }
};

// The IMX708 on either Pi: the Raw role offers the sensor's CSI-2 packed format only (the
// pipelines translate its media bus codes with Packing::CSI2) and proposes it.
std::vector<OfferedFormat> imx708RawRole() {
  return {offeredFormat("SRGGB10_CSI2P", {{1536, 864}, {2304, 1296}, {4608, 2592}})};
}

TEST(NegotiateRawStream, TodaysChoiceIsWhatAPi5ReplacesByItsLossyCompressedRaw) {
  // chooseRawStream alone asks for the proposed packed format, and takes what validation leaves.
  PiCamera pi5{PiCamera::Isp::PiSp};
  const RawStreamChoice byName = chooseRawStream(imx708RawRole(), "SRGGB10_CSI2P", 1280, 720);
  const RawValidation validated = pi5.validate(byName.format, byName.modePx);
  EXPECT_EQ(validated.format, "RGGB_PISP_COMP1");
  EXPECT_FALSE(bayerFormatFromLibcameraName(validated.format));
}

TEST(NegotiateRawStream, APi5LikeCameraRunsRawInTheUnpackedFormatItGrants) {
  PiCamera pi5{PiCamera::Isp::PiSp};
  const RawStreamChoice choice =
      negotiateRawStream(imx708RawRole(), "SRGGB10_CSI2P", 1280, 720, pi5.validator());
  EXPECT_EQ(choice.format, "SRGGB16");
  EXPECT_EQ(choice.requested, "SRGGB10");  // the same bit depth: the same 10-bit sensor mode
  EXPECT_EQ(choice.modePx, (std::pair{2304, 1296}));
  EXPECT_EQ(choice.deliveredPx, (std::pair{1152, 648}));
  EXPECT_TRUE(choice.reason.empty());
  EXPECT_EQ(pi5.asked, (std::vector<std::string>{"SRGGB10_CSI2P", "SRGGB10"}));
  // The swap is said, naming what the packed request became.
  ASSERT_EQ(choice.notes.size(), 2u);
  EXPECT_NE(choice.notes[0].find("RGGB_PISP_COMP1"), std::string::npos) << choice.notes[0];
  EXPECT_NE(choice.notes[1].find("SRGGB10 2304x1296 granted as SRGGB16 2304x1296"),
            std::string::npos)
      << choice.notes[1];
  EXPECT_TRUE(bayerFormatFromLibcameraName(choice.format));
}

TEST(NegotiateRawStream, APi4LikeCameraKeepsTheProposedPackingAfterOneValidation) {
  PiCamera pi4{PiCamera::Isp::Vc4};
  const RawStreamChoice choice =
      negotiateRawStream(imx708RawRole(), "SRGGB10_CSI2P", 1280, 720, pi4.validator());
  EXPECT_EQ(choice.format, "SRGGB10_CSI2P");
  EXPECT_EQ(choice.requested, "SRGGB10_CSI2P");
  EXPECT_EQ(choice.modePx, (std::pair{2304, 1296}));
  EXPECT_EQ(pi4.asked, (std::vector<std::string>{"SRGGB10_CSI2P"}));
  EXPECT_TRUE(choice.notes.empty());
}

TEST(NegotiateRawStream, WhatValidationChangesIsTakenAndSaid) {
  // A Pi 4 with a sensor whose modes are 10-bit, asked for 12: granted at the mode's depth, in
  // the sensor's CFA order.
  PiCamera pi4{PiCamera::Isp::Vc4, BayerOrder::Bggr, 10};
  const RawStreamChoice choice = negotiateRawStream(
      {offeredFormat("SRGGB12_CSI2P", {{2304, 1296}})}, "SRGGB12_CSI2P", 1280, 720, pi4.validator());
  EXPECT_EQ(choice.format, "SBGGR10_CSI2P");
  ASSERT_EQ(choice.notes.size(), 1u);
  EXPECT_EQ(choice.notes[0], "SRGGB12_CSI2P 2304x1296 granted as SBGGR10_CSI2P 2304x1296");
}

TEST(NegotiateRawStream, OnlyCompressedRawOfferedAsksForItsUncompressedTwin) {
  PiCamera pi5{PiCamera::Isp::PiSp};
  const RawStreamChoice choice = negotiateRawStream(
      {offeredFormat("RGGB_PISP_COMP1", {{2304, 1296}}), offeredFormat("YUYV", {{1280, 720}})},
      "RGGB_PISP_COMP1", 1280, 720, pi5.validator());
  EXPECT_EQ(choice.format, "SRGGB16");
  EXPECT_EQ(pi5.asked, (std::vector<std::string>{"SRGGB16"}));
}

TEST(NegotiateRawStream, NothingGrantedDecodableNamesEveryRequestAndFallsBack) {
  // A camera that compresses whatever it is asked for.
  const RawValidator compressing = [](const std::string&, std::pair<int, int> modePx) {
    return RawValidation{false, "RGGB_PISP_COMP1", modePx};
  };
  const RawStreamChoice choice =
      negotiateRawStream(imx708RawRole(), "SRGGB10_CSI2P", 1280, 720, compressing);
  EXPECT_TRUE(choice.format.empty());
  EXPECT_NE(choice.reason.find("SRGGB10_CSI2P 2304x1296 -> RGGB_PISP_COMP1"), std::string::npos)
      << choice.reason;
  EXPECT_NE(choice.reason.find("SRGGB10 2304x1296 -> RGGB_PISP_COMP1"), std::string::npos)
      << choice.reason;
  EXPECT_NE(choice.reason.find("processed stream is used instead"), std::string::npos);
  // A camera that refuses every RAW request.
  const RawValidator refusing = [](const std::string& format, std::pair<int, int> modePx) {
    return RawValidation{true, format, modePx};
  };
  const RawStreamChoice refused =
      negotiateRawStream(imx708RawRole(), "SRGGB10_CSI2P", 1280, 720, refusing);
  EXPECT_TRUE(refused.format.empty());
  EXPECT_NE(refused.reason.find("SRGGB10 2304x1296 refused"), std::string::npos) << refused.reason;
}

TEST(NegotiateRawStream, NoRawOfferedAsksNothing) {
  int calls = 0;
  const RawValidator counting = [&calls](const std::string& format, std::pair<int, int> modePx) {
    ++calls;
    return RawValidation{false, format, modePx};
  };
  const RawStreamChoice choice = negotiateRawStream(
      {offeredFormat("MJPG", {}), offeredFormat("YUYV", {})}, "", 640, 480, counting);
  EXPECT_TRUE(choice.format.empty());
  EXPECT_NE(choice.reason.find("no RAW"), std::string::npos) << choice.reason;
  EXPECT_EQ(calls, 0);
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
