// Slice CSV: round trip, tolerated variations, and errors that name the file and line.
#include "slicecap/io/slice_csv.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "../support/test_support.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

std::string parseError(const std::string& text) {
  std::istringstream in(text);
  try {
    parseSliceCsv(in, "slices.csv");
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(SliceCsv, RoundTripsEverySample) {
  SliceSet set;
  set.add({SliceKind::Axial, {30, 30}}, {{31.2, 359.9}, {29.1, 14.7}, {0.1, 0.2, 0.3}});
  set.add({SliceKind::Diagonal, {75, 30}}, {{74.0, 300.0}, {30.5, 60.0}, {1e-5, 2.5, 123.456789}});
  std::stringstream buffer;
  writeSliceCsv(buffer, set);
  const SliceSet back = parseSliceCsv(buffer, "mem");
  ASSERT_EQ(back.sampleCount(), 2u);
  const SliceSample& s = back.find({SliceKind::Diagonal, {75, 30}})->samples[0];
  EXPECT_DOUBLE_EQ(s.light.thetaDeg, 74.0);
  EXPECT_DOUBLE_EQ(s.view.phiDeg, 60.0);
  EXPECT_NEAR(s.value.b(), 123.456789, 1e-9);
  EXPECT_NEAR(back.find({SliceKind::Axial, {30, 30}})->samples[0].light.phiDeg, 359.9, 1e-9);
}

TEST(SliceCsv, AcceptsCommentsBlankLinesExtraAndReorderedColumns) {
  std::istringstream in(
      "# from the rig\n"
      "frame,r,g,b,slice,theta_v,phi_v,theta_i,phi_i,note\n"
      "\n"
      "17,0.1,0.2,0.3,axial,73.5,105,76,90,ok\n"
      "  # a comment after data\n"
      "18,0.4,0.5,0.6,diagonal,30,30,30,330,\n");
  const SliceSet set = parseSliceCsv(in, "x.csv");
  ASSERT_EQ(set.sampleCount(), 2u);
  const Slice* axial = set.find({SliceKind::Axial, {75, 75}});
  ASSERT_NE(axial, nullptr) << "76 and 73.5 deg belong to the nominal 75/75 pair";
  EXPECT_DOUBLE_EQ(axial->samples[0].light.phiDeg, 90.0);
  EXPECT_DOUBLE_EQ(axial->samples[0].value.r(), 0.1);
  EXPECT_NE(set.find({SliceKind::Diagonal, {30, 30}}), nullptr);
}

TEST(SliceCsv, SkipsTheByteOrderMarkASpreadsheetWritesFirst) {
  // "CSV UTF-8" from a spreadsheet program: EF BB BF, then the header.
  const auto path = test::freshTempDir() / "from-a-spreadsheet.csv";
  std::ofstream(path, std::ios::binary) << "\xEF\xBB\xBFslice,theta_i,phi_i,theta_v,phi_v,r,g,b\r\n"
                                           "axial,30,0,30,15,0.1,0.2,0.3\r\n";
  const SliceSet set = readSliceCsv(path);
  ASSERT_EQ(set.sampleCount(), 1u);
  EXPECT_DOUBLE_EQ(set.find({SliceKind::Axial, {30, 30}})->samples[0].value.b(), 0.3);
  // Only at the start of the file: elsewhere it is a field's text, named in the error.
  const std::string error = parseError(
      "slice,theta_i,phi_i,theta_v,phi_v,r,g,b\n\xEF\xBB\xBF"
      "axial,30,0,30,15,0.1,0.2,0.3\n");
  EXPECT_NE(error.find("slices.csv:2: unknown slice kind"), std::string::npos) << error;
}

TEST(SliceCsv, NamesTheFileAndLineOfATruncatedRow) {
  const std::string error = parseError(
      "slice,theta_i,phi_i,theta_v,phi_v,r,g,b\n"
      "axial,30,0,30,15,0.1,0.2,0.3\n"
      "axial,30,30,30,45,0.1\n");
  EXPECT_NE(error.find("slices.csv:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("expected 8 fields, got 6"), std::string::npos) << error;
}

TEST(SliceCsv, RejectsBadFields) {
  const std::string header = "slice,theta_i,phi_i,theta_v,phi_v,r,g,b\n";
  EXPECT_NE(parseError(header + "axial,30,0,30,15,nan,0.2,0.3\n")
                .find("slices.csv:2: column r is not finite"),
            std::string::npos);
  EXPECT_NE(parseError(header + "axial,30,0,30,15,inf,0.2,0.3\n").find("not finite"),
            std::string::npos);
  EXPECT_NE(parseError(header + "axial,30,0,30,15,0.1x,0.2,0.3\n").find("'0.1x' is not a number"),
            std::string::npos);
  EXPECT_NE(parseError(header + "axial,30,0,30,15,,0.2,0.3\n").find("column r"), std::string::npos);
  EXPECT_NE(parseError(header + "axis,30,0,30,15,0.1,0.2,0.3\n").find("unknown slice kind 'axis'"),
            std::string::npos);
  EXPECT_NE(parseError(header + "axial,95,0,30,15,0.1,0.2,0.3\n").find("theta_i 95 is outside"),
            std::string::npos);
  EXPECT_NE(parseError(header + "axial,30,0,-1,15,0.1,0.2,0.3\n").find("theta_v -1 is outside"),
            std::string::npos);
}

TEST(SliceCsv, RejectsARowWhoseAzimuthsSayAnotherSliceKind) {
  const std::string header = "slice,theta_i,phi_i,theta_v,phi_v,r,g,b\n";
  // A diagonal row labelled axial: Method B would file it under phi_i = 30 of the axial slice.
  EXPECT_NE(parseError(header + "axial,30,0,30,15,0.1,0.2,0.3\naxial,30,30,30,330,0.1,0.2,0.3\n")
                .find("slices.csv:3: axial sample with phi_v - phi_i = -60.0 deg, not 15 deg: is "
                      "its slice kind right?"),
            std::string::npos);
  EXPECT_NE(parseError(header + "diagonal,75,20,75,35,0.1,0.2,0.3\n")
                .find("slices.csv:2: diagonal sample with phi_i + phi_v = 55.0 deg, not 0 or 360"),
            std::string::npos);
  // Jitter of a hand-held capture, a light held 40 deg off its place, wrap-around, the pole and
  // point samples are all accepted.
  for (const char* row : {"axial,30,350,30,8,0.1,0.2,0.3\n", "axial,30,0,30,55,0.1,0.2,0.3\n",
                          "diagonal,30,355,30,8,0.1,0.2,0.3\n",
                          "diagonal,75,-10,75,370,0.1,0.2,0.3\n", "axial,3,0,30,200,0.1,0.2,0.3\n",
                          "diagonal,30,40,5,90,0.1,0.2,0.3\n", "point,30,40,75,90,0.1,0.2,0.3\n"}) {
    EXPECT_EQ(parseError(header + row), "") << row;
  }
}

TEST(SliceCsv, RejectsMissingColumnsAndEmptyFiles) {
  EXPECT_NE(parseError("slice,theta_i,phi_i,theta_v,r,g,b\n").find("no column 'phi_v'"),
            std::string::npos);
  EXPECT_NE(parseError("").find("slices.csv: empty slice CSV"), std::string::npos);
  EXPECT_NE(parseError("# only a comment\n").find("empty"), std::string::npos);
  EXPECT_NE(parseError("slice,theta_i,phi_i,theta_v,phi_v,r,g,b\n").find("no samples"),
            std::string::npos);
}

TEST(SliceCsv, FileErrorsNameThePath) {
  const auto dir = test::freshTempDir();
  try {
    readSliceCsv(dir / "missing.csv");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.csv"), std::string::npos);
  }
  std::ofstream(dir / "bad.csv") << "slice,theta_i,phi_i,theta_v,phi_v,r,g,b\naxial,30,0\n";
  try {
    readSliceCsv(dir / "bad.csv");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:2:"), std::string::npos) << e.what();
  }
}

TEST(SliceCsv, NominalElevationsRoundToTheNearestRing) {
  EXPECT_EQ(nominalElevations(27.6, 77.0), (ElevationPair{30, 75}));
  EXPECT_EQ(nominalElevations(89.0, 0.2), (ElevationPair{75, 0}));
}

}  // namespace
}  // namespace slicecap::io
