// slicecapd's event loop: control requests, frames, the LED, systemd's readiness and watchdog.
#include "slicecap/daemon/daemon.hpp"

#include <signal.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/stat.h>
#include <systemd/sd-daemon.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <iostream>

#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/frame_recorder.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/io/target_json.hpp"

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
  capture::FrameProcessor processor;
  std::optional<int> watchedFd;
  std::optional<EventLoop::TimerId> pollTimer;

  // record_frames: the sweep's recorder, and recorders of ended sweeps still writing their queue
  // (destroying one waits for its writer, which the loop must not do).
  std::unique_ptr<FrameRecorder> recorder;
  std::optional<SliceId> recorderSlice;
  std::vector<std::unique_ptr<FrameRecorder>> retiredRecorders;

  // Texture capture: the texture of the swept slice (while it runs or is paused), and the error
  // its last frame met (the frame loop pauses the sweep on it).
  std::unique_ptr<TextureSink> texture;
  std::optional<SliceId> textureSlice;
  std::string textureError;

  // What the camera could not do as configured, as it said at the last start.
  std::string cameraAdjustment;

  // Sweep-start metering (no exposure configured, a live camera): while it runs the LED stays on
  // and no frame reaches the pipeline; then the exposure stays locked for the sweep. The note
  // says what it did, or why the camera's auto exposure runs instead (then also a warning).
  std::optional<ExposureMeter> meter;
  std::string exposureNote;
  bool exposureUnlocked = false;

  // A live camera's strobe (from the end of the metering to the sweep's stop), its planned
  // switch, and the last run's figures for the status.
  std::optional<LedStrobe> strobeRun;
  std::optional<EventLoop::TimerId> switchTimer;
  std::optional<PlannedSwitch> scheduledSwitch;
  std::optional<StrobeStats> strobeStats;
  std::string strobePattern;

  // The sweep run's decoding (issue 27 item 2): decided on the first frame after the metering,
  // after a response bracket where one is taken (the LED stays on, no frame is processed).
  std::uint32_t locksAccepted = 0;  // the camera's locks since it started
  std::optional<hal::ExposureSetting> lockedSetting;  // the sweep's exposure, once known
  std::optional<ResponseBracket> bracket;
  std::optional<SweepDecoding> decoding;
  std::string decodingWarning;  // shown by every status until the next sweep start
  capture::FrameObserver observer;

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
    if (watchedFd) loop.unwatch(*watchedFd);
    if (pollTimer) loop.cancelTimer(*pollTimer);
    watchedFd.reset();
    pollTimer.reset();
    if (camera) stopQuietly(*camera);
    camera.reset();
    // A metering cut short locked nothing final: its "metering ..." line would outlive it.
    if (meter) exposureNote.clear();
    meter.reset();
    bracket.reset();
    cameraSlice.reset();
    processor = nullptr;
    ledOff();
  }

  void closeTexture() {
    texture.reset();
    textureSlice.reset();
  }

  /// The texture of the slice's sweep (texture capture on); if it cannot be opened, the sweep
  /// pauses with the reason.
  void openTexture(const SliceId& slice) {
    const std::optional<std::filesystem::path> session = manager.sessionDirectory();
    if (!parts.newTextureSink || !session) return;
    try {
      texture = parts.newTextureSink(slice, *session);
      textureSlice = slice;
    } catch (const std::exception& error) {
      manager.pauseSweep(std::string("texture capture: ") + error.what());
    }
  }

  /// A redone sweep's texture starts afresh, as its samples: its folder is discarded durably
  /// before the redo is journaled, so no crash or failure can mix the old sweep's frames into the
  /// new one (texture capture on or off). Throws io::IoError (the redo is then refused).
  void discardTexture(const SweepRedo& redo) {
    const std::optional<std::filesystem::path> session = manager.sessionDirectory();
    // Only a redo the session manager will accept: none while another slice's sweep runs.
    const std::optional<SliceId> swept = manager.sweepSlice();
    if (!session || (swept && *swept != redo.slice)) return;
    if (textureSlice == redo.slice) closeTexture();  // its index would still hold the frames
    io::discardFolderDurably(*session / kTextureFolder / folderName(redo.slice));
  }

  void startCamera(const SliceId& slice) {
    // The last sweep's exposure line is not this one's, whatever happens below.
    meter.reset();
    exposureNote.clear();
    exposureUnlocked = false;
    bracket.reset();
    decoding.reset();
    decodingWarning.clear();
    locksAccepted = 0;
    lockedSetting.reset();
    if (parts.cameraConfig.exposureUs)
      lockedSetting = hal::ExposureSetting{*parts.cameraConfig.exposureUs, parts.cameraConfig.gain};
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
      beginMetering(*opened);
    } catch (const std::exception& error) {
      // The camera runs: stopped here, or (one camera serves every slice) the next sweep's
      // configure would find it streaming. The lock or the LED failed; each names its device.
      stopQuietly(*opened);
      meter.reset();
      exposureNote.clear();
      manager.pauseSweep(std::string("exposure metering: ") + error.what());
      ledOff();
      return;
    }
    // A live camera's strobe starts lit, before its first frame is exposed: a switch while the
    // first frames expose would cost them.
    if (opened->readyDescriptor() && !meter) {
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
    observer = nullptr;
    if (parts.newTextureSink)
      observer = [this](const hal::Frame& frame, const capture::FrameOutcome& outcome,
                        const std::vector<capture::AmbientTerm>& ambient) {
        if (!texture || !textureError.empty()) return;
        try {
          texture->add(frame, outcome, ambient);
        } catch (const io::IoError& error) {
          textureError = std::string("texture storage error: ") + error.what();
        } catch (const std::exception& error) {
          textureError = std::string("texture capture error: ") + error.what();
        }
      };
    processor = parts.newFrameProcessor(slice, observer);
    if (const std::optional<int> fd = camera->readyDescriptor()) {
      watchedFd = *fd;
      loop.watch(*fd, EPOLLIN, [this](std::uint32_t) { pumpFrame(); });
    } else {
      pollTimer = loop.addTimer(parts.filePollInterval, true, [this] { pumpFrame(); });
    }
  }

  void beginMetering(hal::Camera& opened) {
    if (parts.cameraConfig.exposureUs || !opened.readyDescriptor()) return;
    ExposureMeter metering(parts.exposureMeter);
    const hal::ExposureLock lock =
        opened.lockExposure(metering.firstSetting(parts.cameraConfig.gain));
    if (!lock.locked) {
      leaveExposureToCamera(opened.id(), lock.reason);
      return;
    }
    metering.accepted(*lock.locked);
    ++locksAccepted;
    meter = metering;
    exposureNote = "metering the exposure with the LED on";
    parts.led->set(true);
  }

  void leaveExposureToCamera(const std::string& cameraId, const std::string& reason) {
    meter.reset();
    exposureUnlocked = true;
    exposureNote = "camera " + cameraId + ": exposure not locked (" + reason +
                   "): its auto exposure runs through the sweep";
    std::cerr << "slicecapd: " << exposureNote << "\n";
  }

  /// One frame of the metering: measured, never processed; the LED stays on.
  void meterFrame(const hal::Frame& frame) {
    parts.led->set(true);
    const ExposureMeter::Step step = meter->onFrame(frame);
    if (step.kind == ExposureMeter::Step::Kind::Lock) {
      const hal::ExposureLock lock = camera->lockExposure(step.setting);
      if (lock.locked) {
        meter->accepted(*lock.locked);
        ++locksAccepted;
      } else {
        // The setting accepted before stays fixed (a source that refuses part of a lock puts
        // back what it had): the metering ends there, on the next frame.
        meter->refused(lock.reason);
      }
    } else if (step.kind == ExposureMeter::Step::Kind::Done) {
      exposureNote = "camera " + camera->id() + ": " + meter->summary();
      std::cerr << "slicecapd: " << exposureNote << "\n";
      lockedSetting = step.setting;
      meter.reset();
    }
  }

  /// The first frame after the metering: the sweep's decoding without a bracket (a linear
  /// stream, decoding = srgb, a camera that cannot take one), or the bracket's first lock.
  void decideDecoding(const hal::Frame& frame) {
    const std::string id = camera->id();
    if (frame.encoding == PixelEncoding::Linear16 || parts.decoding == DecodingMode::Srgb)
      return applyDecoding(decodingWithoutBracket(frame.encoding, parts.decoding, id, ""));
    const auto fallBack = [&](const std::string& why) {
      applyDecoding(decodingWithoutBracket(frame.encoding, parts.decoding, id, why));
    };
    if (!parts.bracketSubjectFor || !parts.newDecodingFrameProcessor)
      return fallBack("this daemon was started without the target and pipeline a response "
                      "bracket needs (decoding = " + toString(parts.decoding) + ")");
    if (exposureUnlocked || !lockedSetting)
      return fallBack("no response bracket: its exposure is not locked (" + exposureNote +
                      "); set exposure_us and gain, or decoding = srgb");
    bracket.emplace(*lockedSetting, locksAccepted, capture::BracketPlan{},
                    parts.exposureMeter.maxExposureUs);
    const hal::ExposureLock lock = camera->lockExposure(bracket->firstSetting());
    if (!lock.locked) {
      bracket->refused(lock.reason);
      return finishBracket();
    }
    bracket->accepted();
    ++locksAccepted;
    parts.led->set(true);
  }

  /// One frame of the bracket: kept or skipped, never processed; the LED stays on.
  void bracketFrame(const hal::Frame& frame) {
    parts.led->set(true);
    const ResponseBracket::Step step = bracket->onFrame(frame);
    if (step.kind == ResponseBracket::Step::Kind::Lock) {
      const hal::ExposureLock lock = camera->lockExposure(step.setting);
      if (!lock.locked) {
        bracket->refused(lock.reason);
      } else {
        bracket->accepted();
        ++locksAccepted;
      }
    } else if (step.kind == ResponseBracket::Step::Kind::Done) {
      finishBracket();
    }
  }

  void finishBracket() {
    ResponseBracket done = std::move(*bracket);
    bracket.reset();
    // The fit reads the frames' poses and codes: about a second on a Pi, once a sweep run.
    applyDecoding(decodingFromBracket(std::move(done.frames()), done.failure(),
                                      parts.bracketSubjectFor(*cameraSlice), camera->id()));
  }

  /// The sweep run's decoding: the pipeline reads through it, the status and the session say it,
  /// the recording records it (with the bracket frames, under record_frames).
  void applyDecoding(SweepDecoding decided) {
    const std::string id = camera->id();
    std::cerr << "slicecapd: camera " << id << ": decoding " << io::toString(decided.decoding.kind)
              << ": " << decided.note << "\n";
    if (!decided.warning.empty()) std::cerr << "slicecapd: " << decided.warning << "\n";
    decodingWarning = decided.warning;
    if (decided.decoding.kind == io::RecordedDecoding::Kind::MeasuredCurve)
      processor = parts.newDecodingFrameProcessor(*cameraSlice, observer, decided.decoding.curve);
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
    if (recorder) recorder->setDecoding(decided.decoding);
    recordBracket(decided);
    decided.bracketFrames.clear();
    decoding = std::move(decided);
  }

  /// record_frames: the bracket as a recording of its own (no slice; LED on; the fit's decoding),
  /// <session>/brackets/<slice>/run-N, so the fit can be redone on a desktop.
  void recordBracket(SweepDecoding& decided) {
    if (decided.bracketFrames.empty() || !parts.recordingHeaderFor) return;
    const std::optional<std::filesystem::path> session = manager.sessionDirectory();
    if (!session) return;
    const std::filesystem::path folder = *session / kBracketFolder / folderName(*cameraSlice);
    std::filesystem::path directory;
    for (int run = 1;; ++run) {
      directory = folder / ("run-" + std::to_string(run));
      std::error_code ignored;
      if (!std::filesystem::exists(directory, ignored)) break;
    }
    io::Recording header = parts.recordingHeaderFor(*cameraSlice);
    header.slice.reset();
    header.createdBy += " (response bracket)";
    header.decoding = decided.decoding;
    auto writer = std::make_unique<FrameRecorder>(directory, std::move(header),
                                                  decided.bracketFrames.size());
    writer->setDecoding(decided.decoding);
    for (hal::Frame& frame : decided.bracketFrames) writer->offer(std::move(frame));
    retiredRecorders.push_back(std::move(writer));  // writes on its thread, then is dropped
  }

  /// Brings the devices in line with the session state after anything that may change it.
  void reconcile() {
    if (texture && textureSlice != manager.sweepSlice()) closeTexture();
    // The swept slice's texture is open before its frames flow (also after a redo of the running
    // sweep closed it); if it cannot be, the sweep pauses here and no camera starts.
    if (manager.capturing() && !texture) openTexture(*manager.sweepSlice());
    const std::optional<SliceId> wanted =
        manager.capturing() ? manager.sweepSlice() : std::optional<SliceId>();
    if (cameraSlice && cameraSlice != wanted) stopCamera();
    if (wanted && !cameraSlice) startCamera(*wanted);
    if (!manager.capturing()) ledOff();
    reconcileRecorder();
  }

  /// One recorder per sweep of a slice: it lives while the sweep runs or is paused (a continued
  /// sweep appends to its recording) and retires when the sweep stops.
  void reconcileRecorder() {
    const std::optional<SliceId> swept = manager.sweepSlice();
    if (recorder && recorderSlice != swept) {
      retiredRecorders.push_back(std::move(recorder));
      recorderSlice.reset();
    }
    std::erase_if(retiredRecorders, [](const auto& retired) { return retired->idle(); });
    if (!recorder && cameraSlice && parts.recordingHeaderFor) {
      if (const std::optional<std::filesystem::path> session = manager.sessionDirectory()) {
        io::Recording header = parts.recordingHeaderFor(*cameraSlice);
        header.slice = io::RecordedSlice{*cameraSlice, kAxialOffsetDeg};
        recorder = std::make_unique<FrameRecorder>(recordingDirectory(*session, *cameraSlice),
                                                   std::move(header), parts.recordQueueFrames);
        recorderSlice = cameraSlice;
      }
    }
  }

  static std::filesystem::path recordingDirectory(const std::filesystem::path& session,
                                                  const SliceId& slice) {
    return session / "recordings" / folderName(slice);
  }

  /// A redone sweep starts its recording afresh, as its samples.
  void discardRecording(const SliceId& slice) {
    if (recorderSlice == slice) {
      recorder.reset();  // waits for its writer: a person's command, not the frame loop
      recorderSlice.reset();
    }
    retiredRecorders.clear();
    if (const std::optional<std::filesystem::path> session = manager.sessionDirectory()) {
      std::error_code ignored;
      std::filesystem::remove_all(recordingDirectory(*session, slice), ignored);
    }
  }

  nlohmann::json recorderJson() const {
    const RecorderStatus s = recorder->status();
    nlohmann::json json = {{"directory", s.directory.string()},
                           {"frames_written", s.framesWritten},
                           {"frames_queued", s.framesQueued},
                           {"frames_dropped", s.framesDropped}};
    if (!s.error.empty()) json["error"] = "recording stopped: " + s.error;
    return json;
  }

  void pumpFrame() {
    if (!camera || !cameraSlice) return;
    hal::CaptureResult result = camera->nextFrame(std::chrono::milliseconds(0));
    switch (result.status) {
      case hal::CaptureResult::Status::Timeout:
        return;
      case hal::CaptureResult::Status::EndOfStream:
        // A recording played to its end, or the virtual rig's operator went round.
        manager.pauseSweep(camera->readyDescriptor() ? "the camera's stream has ended (" + camera->id() + ")"
                                                     : std::string("the camera's recording has ended"));
        reconcile();
        return;
      case hal::CaptureResult::Status::Error:
        manager.pauseSweep("camera error: " + result.error);
        reconcile();
        return;
      case hal::CaptureResult::Status::Frame:
        break;
    }
    hal::Frame& frame = *result.frame;
    if (meter) {
      try {
        meterFrame(frame);
      } catch (const std::exception& error) {
        // The camera's lock or the LED failed: each message names its device.
        manager.pauseSweep(std::string("exposure metering: ") + error.what());
        reconcile();
      }
      return;
    }
    if (camera->readyDescriptor()) {
      if (!decoding && !bracket) decideDecoding(frame);
      if (bracket) {
        try {
          bracketFrame(frame);
        } catch (const std::exception& error) {
          manager.pauseSweep(std::string("response bracket: ") + error.what());
          reconcile();
        }
        return;
      }
    }
    strobe(frame);
    capture::FrameOutcome outcome;
    try {
      outcome = processor(frame, *cameraSlice);
    } catch (const std::exception& error) {
      outcome.kind = capture::FrameOutcome::Kind::Rejected;
      outcome.rejectReason = "bad_frame";
      outcome.detail = error.what();
    }
    if (outcome.viewElevationErrorDeg)
      manager.noteViewElevationErrorDeg(*outcome.viewElevationErrorDeg);
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
    if (!textureError.empty()) {
      // The sample is kept; the texture stops with the sweep until the person frees space.
      manager.pauseSweep(textureError);
      textureError.clear();
    }
    scheduleSwitch(outcome);
    if (recorder) recorder->offer(std::move(frame));
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
    // What no frame can still need: a few seconds are plenty for any queue of frames.
    commanded->forgetBefore(clock.nowUs() - 5'000'000);
  }

  /// After a live frame: the next switch, timed from what the frames showed.
  void scheduleSwitch(const capture::FrameOutcome& outcome) {
    if (!strobeRun) return;
    strobeRun->noteRows(outcome.measurement.rowsOfInterest);
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
                                  }
                                });
  }

  /// An export into a folder the client names is written with the daemon's rights: only into its
  /// storage, or into a folder the asking uid owns (root may name any). The nearest folder that
  /// exists, links resolved, decides: the export creates the rest inside it.
  void authorizeExport(const Export& command, const std::optional<Peer>& peer) const {
    namespace fs = std::filesystem;
    if (command.directory.empty()) return;
    const fs::path wanted(command.directory);
    for (const fs::path& part : wanted)
      if (part == "..")
        throw RequestError(ErrorCode::BadRequest,
                           "export directory " + command.directory + " must not contain '..'");
    std::error_code error;
    fs::path existing = wanted;
    while (!fs::exists(existing, error) && existing.has_relative_path())
      existing = existing.parent_path();
    const fs::path real = fs::canonical(existing, error);
    if (error)
      throw RequestError(ErrorCode::BadRequest,
                         "export directory " + command.directory + ": " + error.message());
    const fs::path storage = fs::weakly_canonical(parts.storage, error);
    const auto [storageEnd, realEnd] =
        std::mismatch(storage.begin(), storage.end(), real.begin(), real.end());
    if (!error && storageEnd == storage.end()) return;  // the storage or a folder in it
    struct stat folder {};
    if (::stat(real.c_str(), &folder) != 0)
      throw RequestError(ErrorCode::BadRequest,
                         "export directory " + command.directory + ": " + std::strerror(errno));
    if (!peer)
      throw RequestError(
          ErrorCode::PermissionDenied,
          "export into " + command.directory + " refused: the daemon cannot tell who asked");
    if (peer->uid == 0 || folder.st_uid == peer->uid) return;
    throw RequestError(ErrorCode::PermissionDenied,
                       "export into " + command.directory + " refused: " + real.string() +
                           " belongs to uid " + std::to_string(folder.st_uid) + ", not to uid " +
                           std::to_string(peer->uid) +
                           " who asked (export into a folder you "
                           "own, or leave out the directory to export into the session's folder)");
  }

  nlohmann::json handle(const Request& request) {
    if (const auto* exporting = std::get_if<Export>(&request.command))
      authorizeExport(*exporting, request.peer);
    nlohmann::json json;
    try {
      if (const auto* redo = std::get_if<SweepRedo>(&request.command)) {
        try {
          discardTexture(*redo);
        } catch (const io::IoError& error) {
          throw RequestError(ErrorCode::StorageError,
                             std::string("cannot discard the old sweep's texture: ") +
                                 error.what() + " (nothing was redone)");
        }
      }
      json = replyOrThrow(manager.handle(request.command));
    } catch (const RequestError&) {
      reconcile();
      throw;
    }
    if (const auto* redo = std::get_if<SweepRedo>(&request.command)) discardRecording(redo->slice);
    // The recording of a sweep being stopped is reported in the stop's reply.
    if (recorder && (std::holds_alternative<Status>(request.command) ||
                     std::holds_alternative<SweepStop>(request.command)))
      json["recording"] = recorderJson();
    if (texture && (std::holds_alternative<Status>(request.command) ||
                    std::holds_alternative<SweepStop>(request.command)))
      json["texture"] = texture->status();
    if (std::holds_alternative<Status>(request.command)) {
      std::vector<std::string> warnings = parts.warnings;
      if (!cameraAdjustment.empty()) warnings.push_back(cameraAdjustment);
      // The last sweep start's: a camera that could not lock is a warning, shown once.
      if (exposureUnlocked)
        warnings.push_back(exposureNote);
      else if (!exposureNote.empty())
        json["exposure"] = exposureNote;
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
      if (decoding)
        json["decoding"] = {{"decoding", io::toString(decoding->decoding.kind)},
                            {"note", decoding->note}};
      else if (bracket)
        json["decoding"] = {{"decoding", "measuring"},
                            {"note", "taking the response bracket with the LED on"}};
      if (!decodingWarning.empty()) warnings.push_back(decodingWarning);
      if (!warnings.empty()) json["warnings"] = warnings;
    }
    reconcile();
    // A start the devices refused at once (camera, texture) comes back paused, with the reason.
    if ((std::holds_alternative<SweepStart>(request.command) ||
         std::holds_alternative<SweepRedo>(request.command)) &&
        manager.sweepSlice() && !manager.capturing())
      json = manager.status()["sweep"];
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
