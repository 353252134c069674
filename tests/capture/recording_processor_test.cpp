// processRecording reads 8-bit frames through the recording's decoding: a sweep re-encoded with
// the IMX708 curve and saying so gives the samples of the original; read as sRGB it does not.
#include "slicecap/capture/recording_processor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "../support/test_support.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/simulate.hpp"

namespace slicecap::capture {
namespace {

double srgbDecode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

TEST(RecordingDecoding, ProcessReadsFramesThroughTheRecordedCurve) {
  const SliceId slice{SliceKind::Axial, {30, 30}};
  const auto dir = test::freshTempDir() / "sweep";
  sim::SweepSetup setup;
  setup.rig = sim::RigParams::ideal();
  setup.rig.framesPerSlice = 8;
  setup.rig.ambientIrradiance = 0.0;  // 8 frames: the LED-off neighbour is 45 deg away
  setup.materialSpec = "matte-paint";
  const sim::FrameRenderer renderer(setup.camera, setup.target, sim::loadMaterial("matte-paint"),
                                    setup.rig);
  sim::simulateSweep(dir, {slice, kAxialOffsetDeg}, renderer, setup);
  const RecordingResult original = processRecording(dir);

  // The same frames as a camera with the IMX708's curve would have delivered them.
  io::Recording recording = io::readRecording(dir);
  const ToneCurve imx708 = ToneCurve::imx708Tuning();
  for (const io::RecordedFrame& entry : recording.frames) {
    Image image = io::readPng(io::framePath(dir, entry));
    for (std::uint16_t& v : image.samples)
      v = static_cast<std::uint16_t>(std::lround(255.0 * imx708.encode(srgbDecode(v / 255.0))));
    io::writePng(io::framePath(dir, entry), image);
  }
  recording.decoding = io::RecordedDecoding{io::RecordedDecoding::Kind::MeasuredCurve, imx708};
  io::writeRecordingManifest(dir, recording);
  const RecordingResult measured = processRecording(dir);
  PipelineSettings asSrgb;
  asSrgb.toneCurve = ToneCurve::srgb();
  const RecordingResult wrong = processRecording(dir, asSrgb);

  EXPECT_EQ(original.decoding, "srgb");
  EXPECT_EQ(measured.decoding, "imx708-tuning");
  EXPECT_EQ(measured.toJson()["decoding"], "imx708-tuning");
  int compared = 0;
  double worstMeasured = 0.0, worstSrgb = 0.0;
  for (std::size_t i = 0; i < original.outcomes.size(); ++i) {
    const auto& a = original.outcomes[i].sample;
    const auto& b = measured.outcomes[i].sample;
    const auto& c = wrong.outcomes[i].sample;
    if (!a || !b || !c) continue;
    ++compared;
    for (int k = 0; k < 3; ++k) {
      worstMeasured = std::max(worstMeasured, std::abs(b->value[k] / a->value[k] - 1.0));
      worstSrgb = std::max(worstSrgb, std::abs(c->value[k] / a->value[k] - 1.0));
    }
  }
  ASSERT_GE(compared, 3);
  // Re-encoding rounds each sample once more: half a code of the IMX708 curve where it is
  // steepest over the window's and the references' levels is under 1 % of the value.
  EXPECT_LT(worstMeasured, 0.01);
  EXPECT_GT(worstSrgb, 0.05);
}

}  // namespace
}  // namespace slicecap::capture
