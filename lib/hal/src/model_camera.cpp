// The model camera: frame timing, buffer starvation, late controls, rolling shutter against the
// LED's light, noise and colour gains; the ISP beyond them is model_isp_stage's.
#include "slicecap/hal/model_camera.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <random>
#include <stdexcept>

#include "model_exposure.hpp"
#include "slicecap/hal/hal_error.hpp"
#include "slicecap/hal/model_isp_stage.hpp"

namespace slicecap::hal {

using model_exposure::RawCodes;
using model_exposure::RowExposure;
using model_exposure::SampleNoise;

namespace {

struct Lock {
  std::uint64_t fromSequence = 0;
  std::uint64_t reportedFromSequence = 0;  // the first frame whose request carried it
  ExposureSetting setting;
  std::uint32_t index = 0;
};

struct Captured {
  std::uint64_t sequence = 0;
  std::int64_t readoutStartUs = 0;  // row 0's readout start: libcamera's SensorTimestamp
  double exposureUs = 0.0;
  double gain = 1.0;
  std::uint32_t locks = 0;
  std::uint32_t reportedLocks = 0;  // as libcamera counts them: the request carried them
  std::int64_t deliveryUs = 0;
};

}  // namespace

struct ModelCamera::State {
  std::shared_ptr<SceneSource> scene;
  std::shared_ptr<const LedTimeline> led;
  Clock& clock;
  SensorModel model;
  CameraConfig config;
  bool raw = false;  // delivering the RAW stream, decoded
  std::optional<BayerFormat> grantedRaw;  // the RAW format validation granted
  bool configured = false, running = false, ended = false;
  std::int64_t startUs = 0;
  std::uint64_t nextToStart = 0;  // the next frame whose readout has not been decided
  std::deque<Captured> pending;   // captured, not yet taken by the application
  std::vector<Lock> locks;
  std::uint64_t dropped = 0;
  std::mt19937_64 random;
  std::mt19937_64 jitterRandom{model.seed ^ 0x6a6974746572ULL};  // apart from the noise's
  std::optional<model_isp::IspStage> isp;
  std::map<std::uint64_t, FrameTruth> truths;
  int timerFd = -1;
  RoomFlicker flicker;
  double periodUs = 0.0;  // the frame period: the configured frame duration, else the model's

  State(std::shared_ptr<SceneSource> s, std::shared_ptr<const LedTimeline> l, Clock& c,
        SensorModel m)
      : scene(std::move(s)), led(std::move(l)), clock(c), model(std::move(m)), random(model.seed) {
    periodUs = model.framePeriodUs;
    // Its own generator, so the noise draws are those of a model without flicker.
    std::mt19937_64 phaseRandom(model.seed ^ 0x6d61696e73ULL);
    flicker = {model.flickerHz, model.flickerDepth,
               std::uniform_real_distribution<double>(0.0, 1.0)(phaseRandom)};
  }

  std::int64_t readoutStartOf(std::uint64_t sequence) const {
    return startUs + static_cast<std::int64_t>(std::llround(double(sequence) * periodUs));
  }

  Captured planned(std::uint64_t sequence) const {
    Captured frame;
    frame.sequence = sequence;
    frame.readoutStartUs = readoutStartOf(sequence);
    frame.exposureUs = config.exposureUs.value_or(model.autoExposureUs);
    frame.gain = config.gain.value_or(model.autoGain);
    for (const Lock& lock : locks)
      if (lock.fromSequence <= sequence) {
        frame.exposureUs = lock.setting.exposureUs;
        frame.gain = lock.setting.gain.value_or(model.autoGain);
        frame.locks = lock.index;
      }
    for (const Lock& lock : locks)
      if (lock.reportedFromSequence <= sequence) frame.reportedLocks = lock.index;
    frame.deliveryUs = frame.readoutStartUs +
                       static_cast<std::int64_t>(config.heightPx * model.lineTimeUs +
                                                 model.deliveryLatencyUs);
    return frame;
  }

  // Decides every frame whose readout started by `nowUs`: captured if a buffer was free then.
  // Frames the application took before now were taken before that start too (it is asked
  // lazily), so `pending` holds exactly the buffers in use at each start.
  void catchUp(std::int64_t nowUs) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    while (readoutStartOf(nextToStart) <= nowUs) {
      const Captured frame = planned(nextToStart++);
      const bool bufferFree = pending.size() < static_cast<std::size_t>(config.bufferCount);
      if (!bufferFree || uniform(random) < model.dropProbability) {
        ++dropped;
        continue;
      }
      pending.push_back(frame);
    }
  }

  // The time the next frame becomes ready, if the application does nothing meanwhile.
  std::int64_t nextReadyUs() const {
    if (!pending.empty()) return pending.front().deliveryUs;
    return planned(nextToStart).deliveryUs;
  }

  void armTimer() {
    if (timerFd < 0) return;
    const std::int64_t dueUs = std::max<std::int64_t>(nextReadyUs(), 1);
    itimerspec spec{};
    spec.it_value.tv_sec = dueUs / 1'000'000;
    spec.it_value.tv_nsec = (dueUs % 1'000'000) * 1000;
    timerfd_settime(timerFd, TFD_TIMER_ABSTIME, &spec, nullptr);
  }

  // The scene at the middle row's mid-exposure: the rig moves little within one frame.
  std::shared_ptr<const SceneLight> lightFor(const Captured& captured) const {
    const std::int64_t middleUs =
        captured.readoutStartUs +
        static_cast<std::int64_t>(config.heightPx / 2 * model.lineTimeUs - captured.exposureUs / 2);
    std::int64_t sceneStartUs = startUs;
    if (model.holdSceneUntilStrobe) {
      const std::optional<std::int64_t> strobing = led->firstSwitchAfter(startUs, false);
      sceneStartUs = strobing ? *strobing : std::max(startUs, middleUs);
    }
    return scene->lightAt(std::max<std::int64_t>(0, middleUs - sceneStartUs));
  }

  // An empty frame of the configured size, in the encoding the stream delivers.
  Frame emptyFrame() const {
    Frame frame;
    frame.encoding = raw ? PixelEncoding::Linear16 : PixelEncoding::Srgb8;
    frame.image.width = config.widthPx;
    frame.image.height = config.heightPx;
    frame.image.channels = 3;
    frame.image.bitDepth = 8;
    if (!raw) frame.image.samples.resize(std::size_t(config.widthPx) * config.heightPx * 3);
    return frame;
  }

  // Every row over its own exposure window (the rolling shutter) against the LED's light, into
  // `frame`'s samples or, for RAW, `mosaic`; the rows' LED-on fractions into `truth`.
  void exposeRows(const Captured& captured, const SceneLight& light, FrameTruth& truth,
                  Frame& frame, std::vector<std::uint16_t>& mosaic) {
    const double lineUs = model.lineTimeUs, exposureUs = captured.exposureUs;
    const RawCodes codes =
        raw ? model_exposure::rawCodesOf(*model.rawFormat, model.rawBlackLevel16) : RawCodes{};
    const double exposureS = exposureUs * 1e-6;
    SampleNoise noise = model_exposure::sampleNoise(model.fullWellElectrons, model.readNoise);
    const float gains[3] = {float(model.colourGains[0]), float(model.colourGains[1]),
                            float(model.colourGains[2])};
    std::uint16_t* out = frame.image.samples.data();
    noise.at = std::uniform_int_distribution<std::size_t>(
        0, model_exposure::kNoiseTableSize - 1)(random);
    for (int row = 0; row < config.heightPx; ++row) {
      const double rowStartUs = double(truth.row0StartUs) + row * lineUs;
      const double onS = led->onTimeUs(rowStartUs, rowStartUs + exposureUs) * 1e-6;
      truth.rowOnFraction[row] = static_cast<float>(exposureS > 0 ? onS / exposureS : 0.0);
      const double roomFactor = flicker.meanFactor(rowStartUs, exposureUs);
      truth.rowRoomFactor[row] = static_cast<float>(roomFactor);
      RowExposure e{light.ambientRate.data(), light.ledRate.data(),
                    std::size_t(row) * config.widthPx * 3,
                    float(captured.gain * exposureS * roomFactor), float(captured.gain * onS)};
      if (raw)
        model_exposure::exposeRawRow(row, config.widthPx, e, codes, noise, mosaic);
      else
        model_exposure::exposeRgbRow(config.widthPx, e, gains, noise, out);
    }
  }

  void fillMetadata(Frame& frame, const Captured& captured, const FrameTruth& truth) {
    // The timestamp as the receiver's interrupt took it (ModelIsp::timestampJitterUs); row 0's
    // start follows from it as libcamera's does (SensorTimestamp - ExposureTime).
    const std::int64_t jitter = model_isp::timestampJitterUs(model.isp, jitterRandom);
    frame.metadata.sequence = captured.sequence;
    frame.metadata.timestampUs = captured.readoutStartUs + jitter;
    frame.metadata.exposureUs = model.reportsExposure ? captured.exposureUs : 0.0;
    frame.metadata.gain = model.reportsExposure ? captured.gain : 1.0;
    frame.metadata.exposureLocks =
        model.isp.locksCountedByRequest ? captured.reportedLocks : captured.locks;
    frame.metadata.ledOn = false;  // the camera cannot know: whoever drives the LED says
    if (model.reportsExposure) frame.metadata.exposureStartUs = truth.row0StartUs + jitter;
    if (model.reportsLineTime) frame.metadata.lineTimeUs = model.lineTimeUs;
  }

  CaptureResult render(const Captured& captured) {
    const int width = config.widthPx, height = config.heightPx;
    const std::shared_ptr<const SceneLight> light = lightFor(captured);
    if (!light) {
      ended = true;
      return {CaptureResult::Status::EndOfStream, std::nullopt, ""};
    }
    const std::size_t values = std::size_t(width) * height * 3;
    if (light->widthPx != width || light->heightPx != height || light->ledRate.size() != values ||
        light->ambientRate.size() != values)
      return {CaptureResult::Status::Error, std::nullopt,
              id() + ": the scene is " + std::to_string(light->widthPx) + " x " +
                  std::to_string(light->heightPx) + ", the camera " + std::to_string(width) +
                  " x " + std::to_string(height)};
    FrameTruth truth;
    truth.sequence = captured.sequence;
    truth.row0StartUs =
        captured.readoutStartUs - static_cast<std::int64_t>(std::llround(captured.exposureUs));
    truth.exposureUs = captured.exposureUs;
    truth.gain = captured.gain;
    truth.rowOnFraction.resize(height);
    truth.rowRoomFactor.resize(height);
    Frame frame = emptyFrame();
    std::vector<std::uint16_t> mosaic(raw ? values / 3 * 4 : 0);
    exposeRows(captured, *light, truth, frame, mosaic);
    if (raw) {
      model_isp::toGrantedDepth(*model.rawFormat, *grantedRaw, mosaic);
      frame.image = model_exposure::decodedMosaic(*grantedRaw, width, height,
                                                  model.rawBlackLevel16, mosaic);
      frame.black16 = kDecodedBlack16;  // decodeBayer's, as a real camera's RAW frame
    } else {
      isp->process(frame.image);
    }
    fillMetadata(frame, captured, truth);
    truths[captured.sequence] = std::move(truth);
    while (truths.size() > 256) truths.erase(truths.begin());
    return {CaptureResult::Status::Frame, std::move(frame), ""};
  }

  std::string id() const { return "model:" + scene->id(); }
};

ModelCamera::ModelCamera(std::shared_ptr<SceneSource> scene,
                         std::shared_ptr<const LedTimeline> ledLight, Clock& clock,
                         SensorModel model) {
  if (!scene || !ledLight) throw HalError("model camera: needs a scene and an LED");
  if (std::string why; !model.isValid(&why)) throw HalError("model camera: " + why);
  state_ = std::make_unique<State>(std::move(scene), std::move(ledLight), clock, std::move(model));
  if (state_->model.realTime) {
    state_->timerFd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
    if (state_->timerFd < 0)
      throw HalError("model camera: timerfd_create: " + std::string(std::strerror(errno)));
  }
}

ModelCamera::~ModelCamera() {
  if (state_ && state_->timerFd >= 0) ::close(state_->timerFd);
}

std::string ModelCamera::id() const {
  return state_->id();
}

ConfigResult ModelCamera::configure(CameraConfig& config) {
  if (state_->running) throw std::logic_error("ModelCamera::configure while running");
  std::vector<std::string> adjusted;
  const model_isp::RawStream rawStream = model_isp::rawStreamFor(
      state_->model.pipeline, state_->model.rawFormat, config.raw, config.widthPx, config.heightPx);
  if (!rawStream.refusal.empty())
    return {ConfigResult::Status::Invalid, id() + ": " + rawStream.refusal};
  adjusted = rawStream.notes;
  state_->grantedRaw = rawStream.granted;
  state_->raw = state_->grantedRaw.has_value();
  config.rawFormat = state_->raw ? bayerFormatName(*state_->grantedRaw) : std::string();
  const PixelEncoding delivered = state_->raw ? PixelEncoding::Linear16 : PixelEncoding::Srgb8;
  if (config.encoding != delivered) {
    adjusted.push_back(state_->raw ? "encoding set to linear16 (RAW " + config.rawFormat + ")"
                                   : std::string("encoding set to srgb8 (the ISP's 8-bit output)"));
    config.encoding = delivered;
  }
  if (config.bufferCount < 2) {
    adjusted.push_back("buffer count set to 2");
    config.bufferCount = 2;
  }
  state_->periodUs = state_->model.framePeriodUs;
  if (config.frameDurationUs) {
    // A sensor's frame is at least its rows' readout plus some blanking; the model's blanking
    // is 1 ms.
    const double shortestUs = config.heightPx * state_->model.lineTimeUs + 1000.0;
    const double heldUs = std::clamp(*config.frameDurationUs, shortestUs, 1e6);
    if (heldUs != *config.frameDurationUs) {
      adjusted.push_back("frame duration set to " + std::to_string(heldUs) + " us (asked " +
                         std::to_string(*config.frameDurationUs) + " us; this sensor mode's " +
                         "range is " + std::to_string(shortestUs) + "..1000000 us)");
      config.frameDurationUs = heldUs;
    }
    state_->periodUs = heldUs;
  }
  if (config.exposureUs && *config.exposureUs > state_->periodUs) {
    adjusted.push_back("exposure set to the frame period");
    config.exposureUs = state_->periodUs;
  }
  state_->config = config;
  state_->isp.emplace(state_->model);
  state_->configured = true;
  return ConfigResult::fromAdjustments(adjusted);
}

void ModelCamera::start() {
  State& s = *state_;
  if (!s.configured) throw std::logic_error("ModelCamera::start before configure");
  s.running = true;
  s.ended = false;
  s.startUs = s.clock.nowUs();
  s.nextToStart = 0;
  s.pending.clear();
  s.locks.clear();
  s.armTimer();
}

void ModelCamera::stop() {
  State& s = *state_;
  s.running = false;
  s.pending.clear();
  if (s.timerFd >= 0) {
    itimerspec off{};
    timerfd_settime(s.timerFd, 0, &off, nullptr);
  }
}

CaptureResult ModelCamera::nextFrame(std::chrono::milliseconds timeout) {
  State& s = *state_;
  if (!s.running) throw std::logic_error("ModelCamera::nextFrame before start");
  if (s.ended) return {CaptureResult::Status::EndOfStream, std::nullopt, ""};
  const std::int64_t deadlineUs = s.clock.nowUs() + timeout.count() * 1000;
  for (;;) {
    s.catchUp(s.clock.nowUs());
    if (!s.pending.empty() && s.pending.front().deliveryUs <= s.clock.nowUs()) {
      const Captured captured = s.pending.front();
      s.pending.pop_front();
      CaptureResult result = s.render(captured);
      s.armTimer();
      return result;
    }
    const std::int64_t readyUs = s.nextReadyUs();
    if (readyUs > deadlineUs) {
      s.clock.sleepUntilUs(deadlineUs);
      s.armTimer();
      return {CaptureResult::Status::Timeout, std::nullopt, ""};
    }
    s.clock.sleepUntilUs(readyUs);
  }
}

std::optional<int> ModelCamera::readyDescriptor() const {
  if (state_->timerFd < 0) return std::nullopt;
  return state_->timerFd;
}

ExposureLock ModelCamera::lockExposure(const ExposureSetting& wanted) {
  State& s = *state_;
  if (!s.running) throw std::logic_error("ModelCamera::lockExposure outside start..stop");
  s.catchUp(s.clock.nowUs());
  ExposureSetting setting;
  setting.exposureUs = std::clamp(wanted.exposureUs, 1.0, s.periodUs);
  setting.gain = std::clamp(wanted.gain.value_or(s.model.autoGain), 1.0, s.model.maxGain);
  const std::uint32_t index = s.locks.empty() ? 1 : s.locks.back().index + 1;
  // libcamera puts the control in the next request queued: behind the requests the camera
  // already holds (the buffers the application does not), each filled by the next frame.
  const std::size_t queued =
      static_cast<std::size_t>(s.config.bufferCount) - std::min(s.pending.size(),
                                                                std::size_t(s.config.bufferCount));
  s.locks.push_back({s.nextToStart + static_cast<std::uint64_t>(s.model.controlDelayFrames),
                     s.nextToStart + queued, setting, index});
  return {setting, ""};
}

std::optional<FrameTruth> ModelCamera::truth(std::uint64_t sequence) const {
  const auto found = state_->truths.find(sequence);
  if (found == state_->truths.end()) return std::nullopt;
  return found->second;
}

std::uint64_t ModelCamera::framesDropped() const {
  return state_->dropped;
}

RoomFlicker ModelCamera::roomFlicker() const {
  return state_->flicker;
}

double ModelCamera::framePeriodUs() const {
  return state_->periodUs;
}

}  // namespace slicecap::hal
