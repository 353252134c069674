// The camera model's Raspberry Pi platform and ISP behaviours (hal::SensorModel::isp): which Pi
// validates its RAW requests, and what the Pi's ISP does to a processed frame that a measurement
// must survive. Each default is what a Pi does with the Raspberry Pi libcamera fork's own tuning
// files (src/ipa/rpi/{pisp,vc4}/data/imx708.json, v0.7.1+rpt20260429), each cited where it is set.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/camera_modes.hpp"
#include "slicecap/hal/raw_frame.hpp"

namespace slicecap::hal {

/// \brief The Raspberry Pi whose pipeline validates the model's streams: a Pi 4's VideoCore
/// (libcamera's vc4 pipeline) or a Pi 5's PiSP (libcamera's pisp pipeline).
enum class ModelPipeline { Vc4, PiSp };

/// \brief "vc4" | "pisp"; nullopt for anything else.
std::optional<ModelPipeline> parseModelPipeline(std::string_view name);
std::string toString(ModelPipeline pipeline);

/// \brief What `pipeline`'s CameraConfiguration::validate() makes of a RAW stream asked for in
/// `format` on a sensor whose only mode is `sensor` at `sensorModePx`, as the Raspberry Pi fork
/// does (src/libcamera/pipeline/rpi/pisp/pisp.cpp and vc4/vc4.cpp, platformValidate): the CFA
/// order and the size become the sensor's; a Pi 4 applies the sensor's bit depth and keeps CSI-2
/// packed or unpacked; a Pi 5 "cannot output CSI2 packed or non 16-bit output from the frontend":
/// a packed request becomes <ORDER>_PISP_COMP1 (lossy, not decoded), an unpacked one 16-bit
/// words. A format that is not Bayer is refused.
RawValidation validateRawLikePi(ModelPipeline pipeline, const BayerFormat& sensor,
                                std::pair<int, int> sensorModePx, const std::string& format);

/// \brief The RAW stream the model's sensor (`sensor`, one mode of twice `widthPx` x
/// `heightPx`, offered and proposed as libcamera's Raw role offers a Pi sensor's) is granted:
/// negotiateRawStream through validateRawLikePi, as the libcamera backend negotiates on a Pi.
RawStreamChoice negotiateModelRaw(ModelPipeline pipeline, const BayerFormat& sensor, int widthPx,
                                  int heightPx);

/// \brief rpi.ccm of the IMX708 tuning at 4640 K (the same in the pisp and vc4 files); its rows
/// sum to 1, so greys stay grey while saturated colours mix (a red's green goes negative).
inline constexpr std::array<double, 9> kImx708ColourMatrix{
    1.52972, -0.35168, -0.17804, -0.28309, 1.67098, -0.38788, 0.01695, -0.57209, 1.55515};

/// \brief The ISP's processing of the model's processed stream, in the Pi ISP's order: colour
/// gains, the colour matrix, temporal denoise (a Pi 5), the tone curve with its adaptive stretch,
/// then the output format. Identity / off values give the model's earlier fixed pipeline.
struct ModelIsp {
  /// rpi.contrast ce_enable (1 in the IMX708, IMX219 and IMX477 tuning files of both Pis): the
  /// tone curve is composed per frame with a stretch computed from the luminance histogram
  /// (src/ipa/rpi/controller/rpi/contrast.cpp computeStretchCurve, its defaults: the 1 % point
  /// pulled to 1.5 % of full scale by at most 500/65536, the median kept, the 95 % point pushed
  /// to 95 % by at most 2000/65536), from the statistics of the frame before.
  bool adaptiveContrast = true;
  /// rpi.ccm: the colour matrix on linear RGB after the colour gains, row-major (R' = m0 R + m1 G
  /// + m2 B, ...). The identity by default: the model's sensor sees the scene in the scene's own
  /// primaries, without the crosstalk between its colour filters that a Pi's matrix undoes, so
  /// the tuning's matrix (kImx708ColourMatrix) would over-saturate what a Pi merely corrects: a
  /// session of satin-blue-45 read dE 42 with it, its green clipped to 0. Set it to see that
  /// effect, an upper bound on a real sensor's.
  std::array<double, 9> colourMatrix{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// The processed stream's YCbCr encoding, or nullopt for an RGB stream. slicecap's libcamera
  /// backend asks for an RGB format where one is offered, and a Pi's ISP offers RGB888 and
  /// XRGB8888, so the default is RGB; a YUV420 stream is what a Pi's VideoRecording role proposes
  /// ("Rec.709 will be a good default for HD resolutions", pipeline_base.cpp), its chroma at half
  /// the resolution both ways, 8-bit.
  std::optional<YuvEncoding> yuvStream;
  /// rpi.denoise's tdn on a Pi 5 (the pisp tuning files' "tdn": {"deviation": 1.0, ...}; the vc4
  /// files have no temporal denoise): each pixel whose value differs from the previous frame's
  /// output by less than `temporalDenoiseDeviation` standard deviations of its noise is blended
  /// with it, the previous output weighing `temporalDenoiseWeight`. The hardware's blend is not
  /// public: 0.5 is the model's choice. Only on ModelPipeline::PiSp; 0 turns it off.
  double temporalDenoiseWeight = 0.5;
  double temporalDenoiseDeviation = 1.0;
  /// The jitter of the frames' SensorTimestamp, standard deviation in microseconds: the Pi's
  /// timestamp is the CSI-2 receiver's frame-start interrupt as the kernel took it (rpicam-apps
  /// pull request 288), so interrupt latency moves it; 20 us is an estimate, not a measurement.
  double timestampJitterUs = 20.0;
  /// libcamera's count of exposure locks: a frame counts a lock when its request carried it (the
  /// request queued after the lock, behind the bufferCount requests already queued), not when the
  /// sensor took it (libcamera_frames.cpp counts so on a real camera); false: the truth.
  bool locksCountedByRequest = true;

  /// \brief False with a reason naming the field when a value is out of range.
  bool isValid(std::string* error = nullptr) const;
};

/// \brief An ISP of the model's earlier fixed pipeline: no stretch, no colour matrix, RGB, no
/// temporal denoise, no timestamp jitter, locks counted from the truth (tests that compare frames
/// with the scene's light take it).
ModelIsp fixedModelIsp();

}  // namespace slicecap::hal
