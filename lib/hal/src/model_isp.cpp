// The camera model's Pi platform: RAW validation as a Pi 4 or a Pi 5 does it, and the ISP's
// parameters.
#include "slicecap/hal/model_isp.hpp"

#include <cmath>

namespace slicecap::hal {

std::optional<ModelPipeline> parseModelPipeline(std::string_view name) {
  if (name == "vc4") return ModelPipeline::Vc4;
  if (name == "pisp") return ModelPipeline::PiSp;
  return std::nullopt;
}

std::string toString(ModelPipeline pipeline) {
  return pipeline == ModelPipeline::Vc4 ? "vc4" : "pisp";
}

namespace {

// libcamera's name of the PiSP compressed Bayer format of a CFA order (formats.yaml:
// RGGB_PISP_COMP1, ...), which the decoder does not read.
std::string compressedName(BayerOrder order) {
  switch (order) {
    case BayerOrder::Rggb: return "RGGB_PISP_COMP1";
    case BayerOrder::Grbg: return "GRBG_PISP_COMP1";
    case BayerOrder::Gbrg: return "GBRG_PISP_COMP1";
    case BayerOrder::Bggr: return "BGGR_PISP_COMP1";
  }
  return "RGGB_PISP_COMP1";
}

}  // namespace

RawValidation validateRawLikePi(ModelPipeline pipeline, const BayerFormat& sensor,
                                std::pair<int, int> sensorModePx, const std::string& format) {
  const bool compressed = format.find("_PISP_COMP") != std::string::npos;
  std::optional<BayerFormat> asked = bayerFormatFromLibcameraName(format);
  // A compressed request is a 16-bit Bayer format to the pipeline (BayerFormat::Packing::PISP1).
  if (compressed) asked = BayerFormat{sensor.order, 16, BayerPacking::Unpacked16};
  if (!asked) return {true, format, sensorModePx};
  BayerFormat granted{sensor.order, asked->bitDepth, asked->packing};
  if (pipeline == ModelPipeline::Vc4) {
    // vc4.cpp: "Apply the sensor bitdepth"; CSI-2 packed and unpacked both kept.
    granted.bitDepth = sensor.bitDepth;
    return {false, bayerFormatName(granted), sensorModePx};
  }
  // pisp.cpp: "We cannot output CSI2 packed or non 16-bit output from the frontend".
  if (compressed || granted.packing == BayerPacking::Csi2Packed)
    return {false, compressedName(sensor.order), sensorModePx};
  granted.bitDepth = 16;
  return {false, bayerFormatName(granted), sensorModePx};
}

RawStreamChoice negotiateModelRaw(ModelPipeline pipeline, const BayerFormat& sensor, int widthPx,
                                  int heightPx) {
  const std::pair<int, int> modePx{2 * widthPx, 2 * heightPx};
  const std::string name = bayerFormatName(sensor);
  return negotiateRawStream({offeredFormat(name, {modePx})}, name, widthPx, heightPx,
                            [&](const std::string& format, std::pair<int, int>) {
                              return validateRawLikePi(pipeline, sensor, modePx, format);
                            });
}

bool ModelIsp::isValid(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  for (double m : colourMatrix)
    if (!(std::isfinite(m) && std::abs(m) <= 8.0))
      return fail("a colour matrix entry is outside -8..8");
  if (!(temporalDenoiseWeight >= 0.0 && temporalDenoiseWeight < 1.0))
    return fail("temporal denoise weight " + std::to_string(temporalDenoiseWeight) +
                " is outside [0, 1)");
  if (!(temporalDenoiseDeviation >= 0.0 && temporalDenoiseDeviation <= 100.0))
    return fail("temporal denoise deviation " + std::to_string(temporalDenoiseDeviation) +
                " is outside 0..100");
  if (!(timestampJitterUs >= 0.0 && timestampJitterUs <= 1000.0))
    return fail("timestamp jitter " + std::to_string(timestampJitterUs) + " us is outside 0..1000");
  return true;
}

ModelIsp fixedModelIsp() {
  ModelIsp isp;
  isp.adaptiveContrast = false;
  isp.colourMatrix = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  isp.yuvStream.reset();
  isp.temporalDenoiseWeight = 0.0;
  isp.timestampJitterUs = 0.0;
  isp.locksCountedByRequest = false;
  return isp;
}

}  // namespace slicecap::hal
