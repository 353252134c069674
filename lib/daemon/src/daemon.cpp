// slicecapd's event loop: control requests, frames, the LED, systemd's readiness and watchdog.
#include "slicecap/daemon/daemon.hpp"

#include <signal.h>
#include <sys/epoll.h>
#include "sd_daemon.hpp"

#include <algorithm>
#include <csignal>
#include <iostream>

#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/room_light_watch.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/target_json.hpp"
#include "export_authorization.hpp"
#include "sweep_hdr.hpp"
#include "sweep_calibration.hpp"
#include "sweep_outputs.hpp"

namespace slicecap::daemon {

std::vector<int> stopSignals() {
  std::vector<int> signals{SIGTERM,   SIGINT,  SIGHUP,  SIGQUIT, SIGUSR1, SIGUSR2,  SIGALRM,
                           SIGVTALRM, SIGPROF, SIGXCPU, SIGIO,   SIGPWR,  SIGSTKFLT};
  // SIGRTMIN, not 32: the C library keeps the first real-time signals for its threads.
  for (int s = SIGRTMIN; s <= SIGRTMAX; ++s)
    signals.push_back(s);
  return signals;
}

struct Daemon::State {
  DaemonParts parts;
  hal::SteadyClock steadyClock;
  hal::Clock& clock;
  // Every switch the daemon makes, on the camera's clock: the strobe labels frames from it.
  std::shared_ptr<hal::LedTimeline> commanded = std::make_shared<hal::LedTimeline>();
  EventLoop loop{stopSignals()};
  SessionManager manager;
  std::unique_ptr<ControlServer> server;

  // The running sweep's devices; empty while nothing captures.
  std::shared_ptr<hal::Camera> camera;
  std::optional<SliceId> cameraSlice;
  capture::LiveFrameProcessor processor;
  std::optional<int> watchedFd;
  std::optional<EventLoop::TimerId> pollTimer;

  // record_frames and texture capture: what the sweep writes besides its samples.
  SweepOutputs outputs{parts, manager};

  // What the camera could not do as configured, as it said at the last start.
  std::string cameraAdjustment;

  // Sweep-start metering and the sweep run's decoding (no frame is processed meanwhile).
  SweepCalibration calibration{parts};

  // A live camera's strobe (from the end of the metering to the sweep's stop), its planned
  // switch, and the last run's figures for the status.
  std::optional<LedStrobe> strobeRun;
  std::optional<EventLoop::TimerId> switchTimer;
  std::optional<PlannedSwitch> scheduledSwitch;
  std::optional<StrobeStats> strobeStats;
  std::string strobePattern;

  capture::FrameObserver observer;

  // A live HDR sweep (hdr_levels > 1), from the end of the calibration to the sweep's stop.
  SweepHdr hdr{parts.hdrLevels};

  // The room light the sweep run's samples saw (the status warns of a bright or flickering one).
  RoomLightWatch roomLight;

  explicit State(DaemonParts p)
      : parts(std::move(p)),
        clock(parts.clock ? *parts.clock : steadyClock),
        manager(parts.storage, parts.reconstruct, parts.preview, parts.isotropy, parts.material) {
    parts.strobe.alternate = parts.ledAlternate;
    parts.led = std::make_unique<hal::TimelineLed>(std::move(parts.led), clock, commanded);
  }

  void ledOff() noexcept {
    try {
      parts.led->set(false);
    } catch (const std::exception& error) {
      std::cerr << "slicecapd: cannot switch the LED off: " << error.what() << "\n";
    }
  }

  /// A camera stopped on the way out of a failure or a sweep: its own error is logged, not thrown.
  static void stopQuietly(hal::Camera& camera) noexcept {
    try {
      camera.stop();
    } catch (const std::exception& error) {
      std::cerr << "slicecapd: stopping the camera: " << error.what() << "\n";
    }
  }

  void stopStrobe() {
    if (switchTimer) loop.cancelTimer(*switchTimer);
    switchTimer.reset();
    scheduledSwitch.reset();
    if (strobeRun) {
      strobeStats = strobeRun->stats();
      strobePattern = strobeRun->pattern();  // the untimed mode lengthens it
    }
    strobeRun.reset();
  }

  void stopCamera() {
    stopStrobe();
    hdr.stop();
    if (watchedFd) loop.unwatch(*watchedFd);
    if (pollTimer) loop.cancelTimer(*pollTimer);
    watchedFd.reset();
    pollTimer.reset();
    if (camera) stopQuietly(*camera);
    camera.reset();
    calibration.cameraStopped();
    cameraSlice.reset();
    processor = nullptr;
    ledOff();
  }

  void startCamera(const SliceId& slice) {
    // The last sweep's exposure line is not this one's, whatever happens below.
    calibration.reset();
    hdr.reset();
    roomLight.reset();
    std::shared_ptr<hal::Camera> opened;
    try {
      opened = parts.cameraFor(slice);
      hal::CameraConfig config = parts.cameraConfig;
      const hal::ConfigResult result = opened->configure(config);
      if (result.status == hal::ConfigResult::Status::Invalid)
        throw std::runtime_error(opened->id() + ": " + result.reason);
      // What the camera could not do as configured (e.g. no manual exposure) decides whether
      // the sweep's frames are comparable: the journal and the status say it.
      cameraAdjustment.clear();
      if (result.status == hal::ConfigResult::Status::Adjusted) {
        cameraAdjustment =
            "camera " + opened->id() + " adjusted the configuration: " + result.reason;
        std::cerr << "slicecapd: " << cameraAdjustment << "\n";
      }
      opened->start();
    } catch (const std::exception& error) {
      manager.pauseSweep(std::string("camera error: ") + error.what());
      ledOff();
      return;
    }
    try {
      calibration.begin(*opened);
    } catch (const std::exception& error) {
      // The camera runs: stopped here, or (one camera serves every slice) the next sweep's
      // configure would find it streaming. The lock or the LED failed; each names its device.
      stopQuietly(*opened);
      calibration.abandonMetering();
      manager.pauseSweep(std::string("exposure metering: ") + error.what());
      ledOff();
      return;
    }
    // A live camera's strobe starts lit, before its first frame is exposed: a switch while the
    // first frames expose would cost them.
    if (opened->readyDescriptor() && !calibration.metering()) {
      try {
        parts.led->set(true);
      } catch (const std::exception& error) {
        stopQuietly(*opened);
        manager.pauseSweep(std::string("LED error: ") + error.what());
        ledOff();
        return;
      }
    }
    camera = std::move(opened);
    cameraSlice = slice;
    observer = outputs.textureObserver();
    processor = parts.newFrameProcessor(slice, observer);
    if (const std::optional<int> fd = camera->readyDescriptor()) {
      watchedFd = *fd;
      loop.watch(*fd, EPOLLIN, [this](std::uint32_t) { pumpFrame(); });
    } else {
      pollTimer = loop.addTimer(parts.filePollInterval, true, [this] { pumpFrame(); });
    }
  }

  /// The sweep run's decoding: the pipeline reads through it, the status and the session say it,
  /// the recording records it (with the bracket frames, under record_frames).
  void applyDecoding(SweepDecoding decided) {
    const std::string id = camera->id();
    std::cerr << "slicecapd: camera " << id << ": decoding " << io::toString(decided.decoding.kind)
              << ": " << decided.note << "\n";
    if (!decided.warning.empty()) std::cerr << "slicecapd: " << decided.warning << "\n";
    calibration.noteDecodingWarning(decided.warning);
    std::string decodingWarning = decided.warning;
    if (decided.decoding.kind == io::RecordedDecoding::Kind::MeasuredCurve) {
      // Frames the sRGB pipeline still holds settle there first (none, as the decision comes
      // before any frame is processed; a held frame must never be lost silently).
      settleHeld();
      processor = parts.newDecodingFrameProcessor(*cameraSlice, observer, decided.decoding.curve);
    }
    if (const std::optional<std::filesystem::path> session = manager.sessionDirectory()) {
      try {
        std::filesystem::create_directories(*session / kDecodingFolder);
        io::writeJsonFileAtomically(*session / kDecodingFolder / (folderName(*cameraSlice) + ".json"),
                                    toJson(decided, id));
      } catch (const std::exception& error) {
        // The sweep goes on (its samples are what matters); the status shows why it is unrecorded.
        decodingWarning += std::string(decodingWarning.empty() ? "" : "; ") +
                           "the sweep's decoding could not be recorded in the session: " + error.what();
      }
    }
    outputs.setDecoding(decided.decoding);
    outputs.recordBracket(decided, *cameraSlice);
    decided.bracketFrames.clear();
    calibration.noteDecodingWarning(decodingWarning);
    calibration.adopt(std::move(decided));
  }

  /// Brings the devices in line with the session state after anything that may change it.
  void reconcile() {
    outputs.reconcileTexture();
    const std::optional<SliceId> wanted =
        manager.capturing() ? manager.sweepSlice() : std::optional<SliceId>();
    if (cameraSlice && cameraSlice != wanted) stopCamera();
    if (wanted && !cameraSlice) startCamera(*wanted);
    if (!manager.capturing()) ledOff();
    outputs.reconcileRecorder(cameraSlice);
  }

  /// The sweep start's metering and bracket take the frame (true), or it goes to the pipeline.
  bool calibrate(const hal::Frame& frame) {
    if (calibration.metering()) {
      try {
        calibration.meterFrame(*camera, frame);
      } catch (const std::exception& error) {
        // The camera's lock or the LED failed: each message names its device.
        manager.pauseSweep(std::string("exposure metering: ") + error.what());
        reconcile();
      }
      return true;
    }
    if (camera->readyDescriptor()) {
      if (!calibration.decided() && !calibration.bracketing())
        if (std::optional<SweepDecoding> decided = calibration.decide(*camera, frame, *cameraSlice))
          applyDecoding(std::move(*decided));
      if (calibration.bracketing()) {
        try {
          if (std::optional<SweepDecoding> decided =
                  calibration.bracketFrame(*camera, frame, *cameraSlice))
            applyDecoding(std::move(*decided));
        } catch (const std::exception& error) {
          manager.pauseSweep(std::string("response bracket: ") + error.what());
          reconcile();
        }
        return true;
      }
    }
    return false;
  }

  /// The frames the processor holds, settled as the stream ends (before the sweep pauses, so
  /// their samples count).
  void settleHeld() {
    if (!processor || !cameraSlice) return;
    std::vector<capture::SettledFrame> settled;
    try {
      settled = processor(nullptr, *cameraSlice);
    } catch (const std::exception& error) {
      std::cerr << "slicecapd: settling the sweep's last frames: " << error.what() << "\n";
    }
    for (const capture::SettledFrame& frame : settled) apply(frame);
  }

  /// One settled outcome into the session, the HDR cycle and the strobe's rows.
  void apply(const capture::SettledFrame& settled) {
    const capture::FrameOutcome& outcome = settled.outcome;
    if (outcome.viewElevationErrorDeg)
      manager.noteViewElevationErrorDeg(*outcome.viewElevationErrorDeg);
    hdr.noteOutcome(settled.metadata, outcome);
    switch (outcome.kind) {
      case capture::FrameOutcome::Kind::Sample:
        manager.acceptSample(*outcome.sample);
        break;
      case capture::FrameOutcome::Kind::Rejected:
        manager.rejectFrame(outcome.rejectReason);
        break;
      case capture::FrameOutcome::Kind::Ambient:
        break;
    }
    roomLight.note(outcome);
    if (strobeRun) strobeRun->noteRows(outcome.measurement.rowsOfInterest);
  }

  void pumpFrame() {
    if (!camera || !cameraSlice) return;
    hal::CaptureResult result = camera->nextFrame(std::chrono::milliseconds(0));
    switch (result.status) {
      case hal::CaptureResult::Status::Timeout:
        return;
      case hal::CaptureResult::Status::EndOfStream:
        // A recording played to its end, or the virtual rig's operator went round.
        settleHeld();
        manager.pauseSweep(camera->readyDescriptor() ? "the camera's stream has ended (" + camera->id() + ")"
                                                     : std::string("the camera's recording has ended"));
        reconcile();
        return;
      case hal::CaptureResult::Status::Error:
        settleHeld();
        manager.pauseSweep("camera error: " + result.error);
        reconcile();
        return;
      case hal::CaptureResult::Status::Frame:
        break;
    }
    hal::Frame& frame = *result.frame;
    if (calibrate(frame)) return;
    if (camera->readyDescriptor()) hdr.start(camera->id(), calibration.lockedSetting());
    strobe(frame);
    std::vector<capture::SettledFrame> settled;
    try {
      settled = processor(&frame, *cameraSlice);
    } catch (const std::exception& error) {
      capture::FrameOutcome outcome;
      outcome.kind = capture::FrameOutcome::Kind::Rejected;
      outcome.rejectReason = capture::RejectReason::BadFrame;
      outcome.detail = error.what();
      settled = {{frame.metadata, std::move(outcome)}};
    }
    for (const capture::SettledFrame& each : settled) apply(each);
    outputs.pauseOnTextureError();
    scheduleSwitch();
    outputs.record(std::move(frame));
    reconcile();  // a storage error pauses the sweep, and the LED must go off at once
  }

  /// A recorded frame says whether the LED was on, and the LED follows it (its log then shows
  /// what a live run would have done). A live frame is labelled by the strobe from the LED's
  /// timeline over its rows (a frame queued ahead was exposed frames before it arrives).
  void strobe(hal::Frame& frame) {
    if (!camera->readyDescriptor()) {
      parts.led->set(frame.metadata.ledOn);
      return;
    }
    if (!strobeRun) {
      strobeRun.emplace(parts.strobe, *parts.led, commanded, camera->id());
      strobePattern = strobeRun->pattern();
      parts.led->set(true);  // each block starts lit; the metering may have left it so already
    }
    strobeRun->label(frame, clock.nowUs());
    hdr.label(frame);
    // What no frame can still need: a few seconds are plenty for any queue of frames.
    commanded->forgetBefore(clock.nowUs() - 5'000'000);
  }

  /// After a live frame: the next switch, timed from what the frames showed (the rows of
  /// interest of the outcomes settled so far, apply()).
  void scheduleSwitch() {
    if (!strobeRun) return;
    // A planned switch stays planned: frames queued behind a slow one arrive before its time,
    // and planning again at each would put it off for ever (the LED would never switch).
    if (scheduledSwitch) return;
    const std::int64_t nowUs = clock.nowUs();
    // The loop wakes a little late; a switch planned sooner than this is left for the next.
    constexpr std::int64_t kWakeLatencyUs = 1000;
    const std::optional<PlannedSwitch> next = strobeRun->plan(nowUs + kWakeLatencyUs);
    if (!next) return;
    scheduledSwitch = next;
    switchTimer = loop.addTimer(std::chrono::microseconds(std::max<std::int64_t>(1, next->atUs - nowUs)),
                                false, [this, planned = *next] {
                                  switchTimer.reset();
                                  scheduledSwitch.reset();
                                  if (!strobeRun) return;
                                  try {
                                    strobeRun->fire(planned);
                                  } catch (const std::exception& error) {
                                    manager.pauseSweep(std::string("LED error: ") + error.what());
                                    reconcile();
                                    return;
                                  }
                                  if (planned.on && camera) hdr.pairStarted(*camera);
                                });
  }

  /// The status's parts from the capture devices: the exposure, the camera's frames and LED
  /// pattern, the decoding, and the warnings of the configuration, camera and last sweep start.
  void describeDevices(nlohmann::json& json) const {
    std::vector<std::string> warnings = parts.warnings;
    if (!cameraAdjustment.empty()) warnings.push_back(cameraAdjustment);
    calibration.describeExposure(json, warnings);
    hdr.describe(json);
    const std::optional<StrobeStats> shown = strobeRun ? strobeRun->stats() : strobeStats;
    if (shown) {
      const double judged = double(shown->framesClean + shown->framesMixed);
      json["camera_frames"] = {
          {"delivered", shown->framesDelivered},
          {"dropped", shown->framesDropped},
          {"led_pattern", strobeRun ? strobeRun->pattern() : strobePattern},
          {"led_clean_fraction", judged > 0 ? double(shown->framesClean) / judged : 0.0},
          {"timing", shown->timing}};
      if (!shown->warning.empty()) warnings.push_back(shown->warning);
    }
    calibration.describeDecoding(json, warnings);
    if (nlohmann::json room = roomLight.summary(); !room.empty()) {
      json["room_light"] = room;
      for (std::string& warning : roomLight.warnings()) warnings.push_back(std::move(warning));
    }
    if (!warnings.empty()) json["warnings"] = warnings;
  }

  nlohmann::json handle(const Request& request) {
    if (const auto* exporting = std::get_if<Export>(&request.command))
      authorizeExport(*exporting, request.peer, parts.storage);
    nlohmann::json json;
    try {
      if (const auto* redo = std::get_if<SweepRedo>(&request.command)) {
        try {
          outputs.discardTexture(redo->slice);
        } catch (const io::IoError& error) {
          throw RequestError(ErrorCode::StorageError,
                             std::string("cannot discard the old sweep's texture: ") +
                                 error.what() + " (nothing was redone)");
        }
      }
      // A stop settles the LED-on frames still waiting for their LED-off frame first, as the
      // stream's end does: their samples belong to the sweep being stopped.
      if (std::holds_alternative<SweepStop>(request.command) && manager.capturing()) settleHeld();
      json = replyOrThrow(manager.handle(request.command));
    } catch (const RequestError&) {
      reconcile();
      throw;
    }
    if (const auto* redo = std::get_if<SweepRedo>(&request.command))
      outputs.discardRecording(redo->slice);
    // The recording of a sweep being stopped is reported in the stop's reply.
    if (std::holds_alternative<Status>(request.command) ||
        std::holds_alternative<SweepStop>(request.command))
      outputs.describe(json);
    if (std::holds_alternative<Status>(request.command)) describeDevices(json);
    reconcile();
    // A start the devices refused at once (camera, texture) comes back paused, with the reason.
    if ((std::holds_alternative<SweepStart>(request.command) ||
         std::holds_alternative<SweepRedo>(request.command)) &&
        manager.sweepSlice() && !manager.capturing())
      json = control::toJson(*manager.sweepView());
    return json;
  }
};

Daemon::Daemon(DaemonParts parts, int listenFd)
    : state_(std::make_unique<State>(std::move(parts))) {
  // A client that hangs up while a write is on its way must never end the daemon (the control
  // socket sends with MSG_NOSIGNAL; this covers every other write, and a `kill -PIPE`); a file
  // size limit fails the write with EFBIG, which the storage reports, instead of killing it.
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGXFSZ, SIG_IGN);
  state_->ledOff();
  state_->server = std::make_unique<ControlServer>(
      state_->loop, listenFd, [this](const Request& request) { return state_->handle(request); },
      state_->parts.clientLimits);
}

Daemon::~Daemon() {
  state_->stopCamera();
  state_->ledOff();
}

void Daemon::run() {
  state_->loop.onSignal([this](int signalNumber) {
    const char* name = sigabbrev_np(signalNumber);  // none for the real-time signals
    std::cerr << "slicecapd: stopping on "
              << (name ? "SIG" + std::string(name) : "signal " + std::to_string(signalNumber))
              << "\n";
    state_->loop.stop();
  });
  std::uint64_t watchdogUs = 0;
  if (sd_watchdog_enabled(0, &watchdogUs) > 0 && watchdogUs > 0) {
    state_->loop.addTimer(std::chrono::microseconds(watchdogUs / 2), true,
                          [] { sd_notify(0, "WATCHDOG=1"); });
  }
  // A restarted daemon may come back to a paused sweep; nothing captures until a person says so.
  state_->reconcile();
  sd_notify(0, "READY=1");
  try {
    state_->loop.run();
  } catch (...) {
    state_->stopCamera();
    throw;
  }
  sd_notify(0, "STOPPING=1");
  state_->stopCamera();
}

void Daemon::stop() {
  state_->loop.stop();
}

}  // namespace slicecap::daemon
