// slicecapd's core: one event loop serving the control socket, pumping camera frames through the
// capture pipeline into the session, strobing the LED, and talking to systemd.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/exposure_meter.hpp"
#include "slicecap/daemon/led_strobe.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::daemon {

/// \brief Everything the daemon runs with; slicecapd's main builds it from the configuration,
/// tests from fakes.
struct DaemonParts {
  std::filesystem::path storage;
  /// The camera for a sweep of a slice: a live camera returns the one it opened at start (so a
  /// missing camera fails the start, before READY); the file camera opens that slice's recording.
  /// Throws (std::exception with a message) when it cannot.
  std::function<std::shared_ptr<hal::Camera>(const SliceId&)> cameraFor;
  hal::CameraConfig cameraConfig;
  std::unique_ptr<hal::Led> led;
  /// The clock the camera's timestamps use (CLOCK_MONOTONIC on Linux, SteadyClock): the LED's
  /// switches are recorded on it, so that each live frame's rows can be matched to the LED's
  /// state while they were exposed. nullptr: a SteadyClock.
  hal::Clock* clock = nullptr;
  /// Switch the LED off in blocks of frames, so the pipeline can subtract room light; the strobe
  /// places each switch where no sample row is being exposed (LedStrobe).
  bool ledAlternate = true;
  /// The strobe's pattern, guard and readout time (its `alternate` follows ledAlternate).
  StrobeSettings strobe;
  /// When cameraConfig leaves the exposure to a live camera: each sweep start meters it with the
  /// LED on (no frame is processed meanwhile) and locks it for the sweep (ExposureMeter).
  ExposureMeterParams exposureMeter;
  /// slicecapd.conf hdr_levels: on a live camera whose exposure is locked, 2 or 3 exposures
  /// alternated by blocks of LED pairs (HdrCycle), each frame labelled with its level; 1: one.
  int hdrLevels = 1;
  /// A fresh per-frame pipeline for each sweep run of a slice (it keeps tracking state across
  /// frames; the file camera's recordings may each have their own camera and target). The
  /// processor calls the observer (when set: texture capture) for every frame it processes. Its
  /// outcomes may settle frames late (capture::makeLiveFramePipeline: an LED-on frame waits for
  /// the LED-off frame after it); capture::settledAtOnce wraps a processor that needs no wait.
  std::function<capture::LiveFrameProcessor(const SliceId&, capture::FrameObserver)> newFrameProcessor;
  /// slicecapd.conf `decoding` (docs/linear-light.md): how a live camera's 8-bit frames become
  /// linear light. Auto and measured-curve take a response bracket after the metering, when the
  /// two seams below are set; without them (or when the bracket cannot be fitted) the sweep
  /// decodes as sRGB and every status says so, naming the camera.
  DecodingMode decoding = DecodingMode::Auto;
  /// The target and camera model a slice's bracket is fitted against. Empty: no bracket.
  std::function<BracketSubject(const SliceId&)> bracketSubjectFor;
  /// A sweep's pipeline decoding 8-bit frames through `curve` (nullopt: sRGB), called once the
  /// sweep's decoding is known (PipelineSettings::toneCurve). Empty: no bracket.
  std::function<capture::LiveFrameProcessor(const SliceId&, capture::FrameObserver,
                                            const std::optional<ToneCurve>& curve)>
      newDecodingFrameProcessor;
  /// Texture capture (texture_resolution): the texture of a slice's sweep, stored in
  /// <session>/texture (kTextureFolder). Throws (std::exception with a message) when it cannot
  /// be opened, e.g. the session's texture has another resolution; the sweep then pauses. Empty:
  /// no texture is captured.
  std::function<std::unique_ptr<TextureSink>(const SliceId&, const std::filesystem::path& session)>
      newTextureSink;
  ReconstructFunction reconstruct;
  PreviewFunction preview;
  /// The isotropy test status runs once the four diagonal sweeps are complete. Empty: status
  /// never says the axial sweeps can be skipped.
  IsotropyFunction isotropy;
  /// The exported table's fitted material (empty: exports hold none).
  MaterialFunction material;
  /// record_frames: the recording header (camera model, target, slice) of a slice's sweep; every
  /// frame of the sweep is then kept in <session>/recordings/<slice> (FrameRecorder). Empty: no
  /// frames are kept.
  std::function<io::Recording(const SliceId&)> recordingHeaderFor;
  /// Frames waiting for the recorder's writer at most; more are dropped from the recording.
  std::size_t recordQueueFrames = 4;
  /// What the configuration still does wrong for a real capture (configWarnings): every status
  /// shows them, as does what the camera last adjusted of its configuration.
  std::vector<std::string> warnings;
  /// The control socket's client limits: count, idle timeout, the group allowed to connect.
  ServerLimits clientLimits;
  /// How often a camera without a ready descriptor (the file camera) is asked for a frame.
  std::chrono::microseconds filePollInterval = std::chrono::milliseconds(2);
};

/// \brief The signals that stop the daemon cleanly (LED off, camera stopped): every signal whose
/// default action ends the process and that is not a fault of the process itself: SIGTERM
/// (systemd), SIGINT (a terminal), SIGHUP (a dropped SSH session), SIGQUIT, SIGUSR1, SIGUSR2,
/// SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGIO, SIGPWR, SIGSTKFLT and the real-time signals.
/// SIGPIPE and SIGXFSZ are not among them: the Daemon ignores them (a client that hangs up, a file
/// size limit: the write fails and says so). A program that makes a Daemon blocks them with
/// blockSignalsInThisAndLaterThreads before it opens a camera or starts any other thread.
std::vector<int> stopSignals();

/// \brief The daemon. The LED is on only while a sweep is capturing, and off when a sweep pauses
/// or stops, when the camera fails, when run() returns and in the destructor.
class Daemon {
 public:
  /// \brief Takes the listening socket (socket-activated or bound by the caller), switches the
  /// LED off and ignores SIGPIPE and SIGXFSZ in the whole process. Throws io::IoError if the
  /// storage cannot be used.
  Daemon(DaemonParts parts, int listenFd);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  /// \brief Serves until one of stopSignals() (or stop()); tells systemd READY=1 first and pings
  /// its watchdog at half the interval when it asks for one.
  void run();
  /// \brief Thread-safe: makes run() return.
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace slicecap::daemon
