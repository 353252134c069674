// The hardware check's order: frames, the target, the exposure lock, the response, the LED.
#include "slicecap/hwcheck/hardware_check.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "formatted.hpp"
#include "slicecap/hwcheck/check_rig.hpp"
#include "slicecap/hwcheck/exposure_lock_check.hpp"
#include "slicecap/hwcheck/frame_timing.hpp"
#include "slicecap/hwcheck/noise_check.hpp"
#include "slicecap/hwcheck/response_check.hpp"
#include "slicecap/hwcheck/room_light_check.hpp"
#include "slicecap/hwcheck/white_rows.hpp"
#include "slicecap/vision/camera_scaling.hpp"

namespace slicecap::hwcheck {
namespace {


CheckItem skipped(const std::string& name, const std::string& because) {
  return {name, Verdict::Fail, "not measured: " + because, "fix the item above first"};
}

// The camera model at the size the camera delivers; nullopt, with a failed item, when that size
// is another crop than the calibration's (another aspect ratio).
std::optional<vision::CameraModel> cameraModelFor(const vision::CameraModel& calibrated,
                                                  const hal::CameraConfig& configured,
                                                  const std::string& id, HardwareReport& report) {
  const vision::CameraIntrinsics& k = calibrated.intrinsics;
  if (k.widthPx == configured.widthPx && k.heightPx == configured.heightPx) return calibrated;
  if (vision::scalingProblem(calibrated, configured.widthPx, configured.heightPx)) {
    report.items.push_back(
        {"camera", Verdict::Fail,
         id + " delivers " + std::to_string(configured.widthPx) + " x " +
             std::to_string(configured.heightPx) + ", another crop than the calibration's " +
             std::to_string(k.widthPx) + " x " + std::to_string(k.heightPx),
         "set resolution to a size of the calibration's aspect ratio, or calibrate the camera at " +
             std::to_string(configured.widthPx) + " x " + std::to_string(configured.heightPx)});
    return std::nullopt;
  }
  return calibrated.scaledTo(configured.widthPx, configured.heightPx);
}

// RAW is the best a camera can give: linear light with no ISP curve to measure.
std::optional<CheckItem> rawStreamItem(const hal::CameraConfig& configured, const std::string& id) {
  if (configured.rawFormat.empty()) return std::nullopt;
  return CheckItem{"RAW", Verdict::Ok,
                   id + " delivers its RAW stream " + configured.rawFormat +
                       ", decoded here to linear light at " + std::to_string(configured.widthPx) +
                       " x " + std::to_string(configured.heightPx) +
                       ": the sweeps need no response curve",
                   ""};
}

// The frames' period, jitter and drops, with the LED on; fills the frame items and figures.
FrameTiming checkFrames(CheckRig& rig, HardwareReport& report, const HardwareCheckOptions& options,
                        std::vector<SeenFrame>& frames) {
  rig.setLed(true);
  frames = rig.collect(std::int64_t(std::llround(options.captureSeconds * 1e6)));
  const FrameTiming timing = measureFrameTiming(frames);
  report.items.push_back(frameTimingItem(timing, report.cameraId));
  report.figures.framesSeen = timing.frames + timing.dropped;
  report.figures.framesDropped = timing.dropped;
  if (timing.hasTimestamps) {
    report.figures.framePeriodUs = timing.periodUs;
    report.figures.frameJitterUs = timing.jitterUs;
  }
  return timing;
}

// The target, from the newest frames (the first ones may still be settling their exposure), and
// its white rows; nullopt, with a failed item, when it is not in view.
std::optional<WhiteRows> checkTarget(const std::vector<SeenFrame>& frames,
                                     const vision::TargetGeometry& target,
                                     const vision::CameraModel& cameraModel,
                                     HardwareReport& report) {
  const std::string& id = report.cameraId;
  std::optional<vision::Pose> pose;
  for (std::size_t i = frames.size(); i-- > 0 && !pose && frames.size() - i <= 5;)
    pose = locateTarget(frames[i].frame, target, cameraModel);
  std::optional<WhiteRows> whites;
  if (pose) whites = whiteRowsOf(target, cameraModel, *pose);
  if (!whites || whites->firstRow < 0) {
    report.items.push_back(
        {"target", Verdict::Fail,
         "the target (" + target.name + ") is not in view of " + id + " (fewer than 4 of its markers found)",
         "put the whole printed target under the camera, lit by the LED and in focus; with a "
         "target of your own, set target = its JSON; with a lens other than the nominal one, set "
         "calibration"});
    return std::nullopt;
  }
  report.items.push_back({"target", Verdict::Ok,
                          "found; its white references cover rows " +
                              std::to_string(whites->firstRow) + ".." +
                              std::to_string(whites->lastRow),
                          ""});
  return whites;
}

// The response curve, unless the frames are linear or it cannot be measured; the codes that
// decode the frames when it was fitted. Updates `brightExposureUs` to the metered exposure.
std::optional<capture::CodeTable> checkResponseCurve(
    CheckRig& rig, HardwareReport& report, const vision::TargetGeometry& target,
    const vision::CameraModel& cameraModel, bool linearFrames, const WhiteRows* whites,
    const ExposureLockResult& lock, const HardwareCheckOptions& options, double& brightExposureUs) {
  const std::string& id = report.cameraId;
  std::optional<capture::CodeTable> codes;
  if (linearFrames) {
    // RAW decoded here, or a 16-bit linear stream: the sensor's own response, linear to well
    // within what the capture resolves; there is no ISP curve to measure.
    report.items.push_back({"response curve", Verdict::Ok,
                            "not needed: " + id + " delivers linear frames (" +
                                std::string(toString(PixelEncoding::Linear16)) + ")",
                            ""});
  } else if (!whites) {
    report.items.push_back(skipped("response curve", "the target is not in view"));
  } else if (lock.refused) {
    report.items.push_back(skipped("response curve", "the exposure cannot be locked"));
  } else {
    const ResponseCheck response = checkResponse(rig, target, cameraModel, options.bracket);
    report.items.push_back(responseItem(response, id));
    report.figures.curveFromLinear = response.fromLinear;
    report.figures.curveFromSrgb = response.fromSrgb;
    if (response.fit) {
      codes.emplace(response.fit->curve);
      report.responseCurve = response.fit->curve;
      report.responseRange = {response.fit->lowestCode, response.fit->highestCode};
    }
    if (response.meteredExposureUs > 0) brightExposureUs = response.meteredExposureUs;
  }
  return codes;
}

void checkNoise(CheckRig& rig, HardwareReport& report, const WhiteRows* whites,
                const ExposureLockResult& lock, const capture::CodeTable& codes,
                double brightExposureUs) {
  if (!whites) {
    report.items.push_back(skipped("sensor noise", "the target is not in view"));
    return;
  }
  if (lock.refused) {
    report.items.push_back(skipped("sensor noise", "the exposure cannot be locked"));
    return;
  }
  // The white references at about 0.35, 0.09 and 0.02 of full scale: shot noise dominates the
  // first, read noise the last.
  const NoiseResult noise = measureSensorNoise(
      rig, *whites, codes, {brightExposureUs, brightExposureUs / 4.0, brightExposureUs / 16.0});
  report.items.push_back(sensorNoiseItem(noise, report.cameraId));
  if (noise.noise) {
    report.figures.sensorReadNoise = noise.noise->readNoise;
    report.figures.sensorFullWellElectrons = noise.noise->fullWellElectrons;
    report.configLines.emplace_back("sensor_read_noise", formatted("%.5f", noise.noise->readNoise));
    report.configLines.emplace_back("sensor_full_well_electrons",
                                    formatted("%.0f", noise.noise->fullWellElectrons));
  }
}

void checkLedTiming(CheckRig& rig, HardwareReport& report, const FrameTiming& timing,
                    const WhiteRows* whites, const capture::CodeTable& codes,
                    double brightExposureUs, const HardwareCheckOptions& options) {
  if (!timing.hasTimestamps) {
    report.items.push_back(skipped("LED timing and readout", "the frames have no timestamps"));
    return;
  }
  if (!whites) {
    report.items.push_back(skipped("LED timing and readout", "the target is not in view"));
    return;
  }
  const LedTiming led =
      measureLedTiming(rig, *whites, codes, timing.periodUs, brightExposureUs, options.led);
  report.items.push_back(ledTimingItem(led, report.cameraId));
  report.figures.lineTimeUs = led.lineTimeUs;
  report.figures.readoutUs = led.readoutUs;
  report.figures.ledOffsetUs = led.offsetUs;
  report.figures.ledOffsetSpreadUs = led.residualUs;
  if (!led.readoutUs) return;
  report.figures.deliveryLatencyUs = timing.timestampToArrivalUs - *led.readoutUs;
  report.items.push_back(
      {"delivery latency", Verdict::Ok,
       formatted("frames arrive %.1f ms after their last row is read out", *report.figures.deliveryLatencyUs / 1000.0) +
           formatted(" (%.1f frame periods after their first row)", timing.timestampToArrivalUs / timing.periodUs),
       ""});
  report.configLines.emplace_back("readout_us", formatted("%.0f", *led.readoutUs));
  report.configLines.emplace_back("led_guard_us", formatted("%.0f", guardFor(*led.offsetUs, *led.residualUs)));
}

// The room light from LED-off frames: its flicker and its level against the LED's, at the
// exposure the sweeps lock.
void checkRoomLight(CheckRig& rig, HardwareReport& report, const FrameTiming& timing,
                    const WhiteRows* whites, const ExposureLockResult& lock,
                    const capture::CodeTable& codes, double brightExposureUs, int heightPx) {
  if (!timing.hasTimestamps) {
    report.items.push_back(skipped("room light", "the frames have no timestamps"));
    return;
  }
  if (!whites) {
    report.items.push_back(skipped("room light", "the target is not in view"));
    return;
  }
  if (lock.refused) {
    report.items.push_back(skipped("room light", "the exposure cannot be locked"));
    return;
  }
  // The rows' spacing as the LED timing measured it, else the readout over the rows, else a
  // frame period over them (a rolling shutter takes at most that).
  const double lineTimeUs = report.figures.lineTimeUs  ? *report.figures.lineTimeUs
                            : report.figures.readoutUs ? *report.figures.readoutUs / heightPx
                                                       : timing.periodUs / heightPx;
  const RoomLightResult room =
      measureRoomLight(rig, *whites, codes, brightExposureUs, 1.0, lineTimeUs, timing.periodUs);
  report.items.push_back(roomLightItem(room, report.cameraId));
  report.figures.roomToLed = room.roomToLed;
  if (room.flicker.hz) {
    report.figures.flickerHz = room.flicker.hz;
    report.figures.flickerDepth = room.flicker.depth;
    if (const std::optional<int> mains = mainsOfFlicker(*room.flicker.hz))
      report.configLines.emplace_back("mains_hz", std::to_string(*mains));
  }
}

// Everything after the camera has started; throws what CheckRig throws.
void runChecks(CheckRig& rig, HardwareReport& report, const vision::TargetGeometry& target,
               const vision::CameraModel& cameraModel, bool linearFrames,
               const HardwareCheckOptions& options) {
  std::vector<SeenFrame> frames;
  const FrameTiming timing = checkFrames(rig, report, options, frames);
  const std::optional<WhiteRows> whites = checkTarget(frames, target, cameraModel, report);
  const WhiteRows* whitesPtr = whites ? &*whites : nullptr;

  const ExposureLockResult lock = checkExposureLock(rig, whitesPtr);
  report.items.push_back(exposureLockItem(lock, report.cameraId));
  if (lock.metadataDelayFrames) report.figures.exposureLockDelayFrames = lock.metadataDelayFrames;
  else if (lock.brightnessDelayFrames) report.figures.exposureLockDelayFrames = lock.brightnessDelayFrames;

  double brightExposureUs = lock.toUs > 0 ? lock.toUs * 2.0 : 10000.0;
  const std::optional<capture::CodeTable> codes = checkResponseCurve(
      rig, report, target, cameraModel, linearFrames, whitesPtr, lock, options, brightExposureUs);
  checkNoise(rig, report, whitesPtr, lock, codes ? *codes : capture::CodeTable::srgb(),
             brightExposureUs);
  checkLedTiming(rig, report, timing, whitesPtr, codes ? *codes : capture::CodeTable::srgb(),
                 brightExposureUs, options);
  checkRoomLight(rig, report, timing, whitesPtr, lock, codes ? *codes : capture::CodeTable::srgb(),
                 brightExposureUs, frames.empty() ? 720 : frames.front().frame.image.height);
}

}  // namespace

HardwareReport runHardwareCheck(hal::Camera& camera, hal::CameraConfig config, hal::Led& led,
                                hal::Clock& clock, const vision::TargetGeometry& target,
                                const vision::CameraModel& cameraModel, const BackendInfo& backend,
                                const HardwareCheckOptions& options) {
  HardwareReport report;
  report.cameraId = camera.id();
  report.cameras = backend.cameras;
  const std::string& id = report.cameraId;
  std::optional<CheckItem> rawItem;  // set when the camera delivers a RAW stream
  bool started = false;
  try {
    const int askedWidthPx = config.widthPx, askedHeightPx = config.heightPx;
    const hal::ConfigResult configured = camera.configure(config);
    if (configured.status == hal::ConfigResult::Status::Invalid) {
      report.items.push_back({"camera", Verdict::Fail, id + " cannot be configured: " + configured.reason,
                              "set resolution to a mode the camera lists"});
    } else {
      const bool sizeChanged = config.widthPx != askedWidthPx || config.heightPx != askedHeightPx;
      const bool valid = configured.status == hal::ConfigResult::Status::Valid;
      report.items.push_back(
          {"camera", valid ? Verdict::Ok : Verdict::Warn,
           id + " at " + std::to_string(config.widthPx) + " x " + std::to_string(config.heightPx) +
               (configured.reason.empty() ? std::string() : " (adjusted: " + configured.reason + ")"),
           valid ? ""
           : sizeChanged
               ? "the calibration is scaled to the delivered size; for the best poses set "
                 "resolution to it and calibrate at that size"
               : "the camera changed what was asked (above): the check and the sweeps run with it"});
      rawItem = rawStreamItem(config, id);
      // The frames come at the size configure settled on (a binned RAW stream is half its
      // sensor mode): the camera model follows it, as slicecapd's does, or the target's rows
      // and the pose would be read through the calibration of another size.
      const std::optional<vision::CameraModel> delivered = cameraModelFor(cameraModel, config, id, report);
      if (delivered) {
        camera.start();
        started = true;
        CheckRig rig(camera, led, clock);
        runChecks(rig, report, target, *delivered, config.encoding == PixelEncoding::Linear16, options);
      }
    }
  } catch (const std::exception& error) {
    report.items.push_back({"camera", Verdict::Fail, std::string("the check stopped: ") + error.what(),
                            "check the camera's cable and that no other program (or a running "
                            "slicecapd) uses it; camera and camera_device in slicecapd.conf"});
  }
  report.items.push_back(rawItem ? *rawItem
                                 : CheckItem{"RAW", backend.rawVerdict, backend.rawFinding, backend.rawAdvice});
  try {
    led.set(false);
  } catch (const std::exception& error) {
    report.items.push_back({"LED", Verdict::Fail, std::string("cannot switch the LED off: ") + error.what(),
                            "check led_chip and led_line"});
  }
  if (started) camera.stop();
  return report;
}

}  // namespace slicecap::hwcheck
