// A camera model that behaves like a real rolling-shutter sensor behind an ISP, for tests, the
// virtual rig and `camera = model`: queued buffers, late controls, dropped frames, a tone curve.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/core/tone_curve.hpp"
#include "slicecap/hal/bayer_frame.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/hal/model_isp.hpp"
#include "slicecap/hal/room_flicker.hpp"

namespace slicecap::hal {

/// \brief What the sensor sees, as linear RGB per second of exposure at unit gain (1 = full
/// scale), split into the LED's share and the room light's, 3 floats a pixel, row-major.
struct SceneLight {
  int widthPx = 0;
  int heightPx = 0;
  std::vector<float> ledRate;
  std::vector<float> ambientRate;
};

/// \brief The scene in front of the model camera (the virtual rig renders it).
class SceneSource {
 public:
  virtual ~SceneSource() = default;
  virtual std::string id() const = 0;
  /// \brief The light `sinceStartUs` after the camera started; nullptr once the scene is over
  /// (the virtual operator has gone round). May take long (it renders): the model calls it while
  /// it makes a frame the application asked for, as a slow ISP would.
  virtual std::shared_ptr<const SceneLight> lightAt(std::int64_t sinceStartUs) = 0;
};

/// \brief How the model sensor and ISP behave. Defaults follow a Raspberry Pi camera module 3
/// (IMX708) at 1280 x 720 and 30 fps behind the Pi's ISP.
struct SensorModel {
  double framePeriodUs = 33333.0;
  /// Row-to-row start delay: 720 rows read out in 28.8 ms, most of the frame period.
  double lineTimeUs = 40.0;
  /// From the end of a frame's readout to its arrival at the application (ISP and buffer hand-off).
  double deliveryLatencyUs = 12000.0;
  /// Frames between the next frame to start and the first one taken with a new exposure: the
  /// requests already queued and the sensor's own delay (picamera2 issues 1278, 1333).
  int controlDelayFrames = 3;
  double dropProbability = 0.0;  ///< frames lost on the link besides those without a free buffer
  ToneCurve tone = ToneCurve::imx708Tuning();
  /// The ISP's fixed colour gains on linear RGB before the tone curve (white balance: a sensor's
  /// red and blue are weaker than its green).
  std::array<double, 3> colourGains{1.9, 1.0, 1.6};
  double readNoise = 0.002;           ///< fraction of full scale, standard deviation
  double fullWellElectrons = 8000.0;  ///< shot noise: electrons at full scale (0: none)
  double autoExposureUs = 15000.0;    ///< the camera's own exposure until one is locked
  double autoGain = 1.0;
  double maxGain = 16.0;
  /// The room light's flicker (the scene's ambientRate is its mean): lamps on AC mains flicker at
  /// twice the mains frequency, 100 Hz in a 50 Hz country (IEEE Std 1789-2015, section 1; Lehman
  /// et al., "Proposing measures of flicker in the low frequencies for lighting applications",
  /// 2011). Depth 0.10, IEEE 1789's "percent flicker" of 10 %: a filament lamp's 6-12 % at
  /// 100/120 Hz (Lehman et al.), just above IEEE 1789's low-risk line for LED lighting at 100 Hz
  /// (0.08 x 100 = 8 %); magnetic-ballast fluorescent tubes and cheap LED drivers reach 30-100 %.
  /// Each row integrates it over its own exposure window, starting at its own time (the rolling
  /// shutter): a short exposure shows bands, an exposure of whole flicker periods none. The phase
  /// against the steady clock comes from `seed` (the mains does not know the camera).
  double flickerHz = 100.0;
  double flickerDepth = 0.10;
  /// A RAW stream the sensor offers (nullopt: none). With it and CameraConfig::raw Auto or On,
  /// the model is a sensor of twice the configured size in this Bayer format (a Pi 4's IMX708:
  /// SRGGB10_CSI2P): each scene pixel is a 2 x 2 cell whose R, two G and B samples see its
  /// linear light with their own noise, no colour gains and no tone curve, offset by the black
  /// level and quantised to the format's codes; the bytes are packed as the sensor packs them and
  /// decoded by decodeBayer, so frames are Linear16 at the configured size.
  std::optional<BayerFormat> rawFormat;
  /// The Pi whose pipeline validates the streams: a RAW request is negotiated through
  /// negotiateRawStream against validateRawLikePi, so on PiSp the packed format becomes
  /// <ORDER>_PISP_COMP1 and the unpacked twin is granted as 16-bit words (the sensor's codes in
  /// their top bits). PiSp by default: a Pi 5 is the board sold now, and the one whose
  /// validation a RAW request must survive twice.
  ModelPipeline pipeline = ModelPipeline::PiSp;
  /// The processed stream's ISP beyond the colour gains and the tone curve, and what the frames'
  /// metadata say as libcamera says it (timestamp jitter, lock counting); fixedModelIsp() for the
  /// earlier fixed pipeline.
  ModelIsp isp;
  /// The sensor's black level on the 16-bit scale, as libcamera reports it (SensorBlackLevels):
  /// 4096, 64 at 10 bits, the IMX708's tuning.
  double rawBlackLevel16 = kDefaultBlackLevel16;
  /// Whether frames carry the line time (libcamera does not say it on a Pi; a model may).
  bool reportsLineTime = false;
  /// Whether frames carry their exposure (uvcvideo does not).
  bool reportsExposure = true;
  /// The scene stands still until the LED first goes off after start (a person holds the rig
  /// while the daemon meters the exposure with the LED on, and moves once it strobes), then
  /// runs from its start; false: the scene runs from start().
  bool holdSceneUntilStrobe = true;
  /// Real time (a timer descriptor for the daemon's poll loop, the steady clock) or a FakeClock
  /// that nextFrame() advances.
  bool realTime = true;
  std::uint64_t seed = 1;

  /// \brief False with a reason naming the field when a value is out of range.
  bool isValid(std::string* error = nullptr) const;
};

/// \brief What really happened to one delivered frame (tests compare the capture's view with it).
struct FrameTruth {
  std::uint64_t sequence = 0;
  std::int64_t row0StartUs = 0;
  double exposureUs = 0.0;
  double gain = 1.0;
  std::vector<float> rowOnFraction;  ///< the LED's share of each row's exposure, as it shone
  /// The room light each row integrated, as a multiple of its mean (RoomFlicker::meanFactor).
  std::vector<float> rowRoomFactor;
};

/// \brief The model camera. Frame k's row r is exposed over [k * period + r * lineTime -
/// exposure, k * period + r * lineTime) after start, against the physical LED's timeline, and
/// delivered after its last row is read out plus the latency. A frame whose readout starts while
/// every buffer holds a frame the application has not taken is dropped (a sequence gap), as
/// libcamera's pipelines drop when no request is queued. Frames are 8-bit: the scene's linear
/// light with shot and read noise, the ISP's colour gains and tone curve. Metadata as libcamera's
/// Pi pipeline reports it: the timestamp is the start of row 0's readout.
class ModelCamera final : public Camera {
 public:
  /// \brief `ledLight`: the timeline of the light itself (a TimelineLed with the LED's own
  /// delay). Throws HalError for an invalid model.
  ModelCamera(std::shared_ptr<SceneSource> scene, std::shared_ptr<const LedTimeline> ledLight,
              Clock& clock, SensorModel model = {});
  ~ModelCamera() override;

  std::string id() const override;
  /// \brief Holds CameraConfig::frameDurationUs as the frame period when set (adjusted up to the
  /// rows' readout plus 1 ms when shorter, as a sensor's minimum frame length; 1 s at most).
  /// Adjusts the encoding to 8-bit sRGB (the ISP's output, whatever its real curve), or
  /// to linear16 when the RAW stream is taken (SensorModel::rawFormat and CameraConfig::raw not
  /// Off, negotiated with the pipeline's validation; CameraConfig::rawFormat names the format
  /// granted, and what validation did to the requests before it is said as an adjustment), and
  /// the buffer count to at least 2. Invalid when CameraConfig::raw is On and no decodable RAW
  /// format is granted (the reason names each request and what it became).
  ConfigResult configure(CameraConfig& config) override;
  void start() override;
  void stop() override;
  CaptureResult nextFrame(std::chrono::milliseconds timeout) override;
  std::optional<int> readyDescriptor() const override;
  /// \brief Takes effect controlDelayFrames after the next frame to start; clamped to the frame
  /// period and the gain range.
  ExposureLock lockExposure(const ExposureSetting& wanted) override;

  /// \brief The truth of a frame delivered recently (the last 256), or nullopt.
  std::optional<FrameTruth> truth(std::uint64_t sequence) const;
  /// \brief Frames lost so far (no free buffer, or the link).
  std::uint64_t framesDropped() const;
  /// \brief The room light's flicker as this camera sees it (its phase drawn from the seed).
  RoomFlicker roomFlicker() const;
  /// \brief The frame period frames are taken at (the configured frame duration, else the
  /// model's).
  double framePeriodUs() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::hal
