// What the daemon runs with: its three collaborators (CaptureRig, SessionOutputs, SessionTables),
// the LED and the settings of the sweep's devices. lib/rig's daemonPartsFrom fills it from
// slicecapd.conf; tests from fakes.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/control/reply_views.hpp"
#include "slicecap/daemon/capture_rig.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/exposure_meter.hpp"
#include "slicecap/daemon/led_strobe.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/daemon/session_outputs.hpp"
#include "slicecap/daemon/session_tables.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led.hpp"

namespace slicecap::daemon {

/// \brief Everything the daemon runs with: its three collaborators (CaptureRig, SessionOutputs,
/// SessionTables; lib/rig builds them from slicecapd.conf, tests from fakes), the LED and the
/// settings of the sweep's devices.
struct DaemonParts {
  std::filesystem::path storage;
  /// The camera and pipeline of each slice's sweep, and its response bracket's subject.
  std::unique_ptr<CaptureRig> rig;
  /// The raw-frame recordings and the texture (nullptr: a sweep keeps only its samples).
  std::unique_ptr<SessionOutputs> outputs;
  /// The reconstruction, previews, fitted material and isotropy test.
  std::unique_ptr<SessionTables> tables;
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
  /// slicecapd.conf hdr_levels (validated by readDaemonConfig: 1..3): on a live camera whose
  /// exposure is locked, 2 or 3 exposures alternated by blocks of LED pairs (HdrCycle), each
  /// frame labelled with its level; 1: one.
  int hdrLevels = 1;
  /// slicecapd.conf `decoding` (docs/linear-light.md): how a live camera's 8-bit frames become
  /// linear light. Auto and measured-curve take a response bracket after the metering when the
  /// rig has a bracket subject; without one (or when the bracket cannot be fitted) the sweep
  /// decodes as sRGB and every status says so, naming the camera.
  DecodingMode decoding = DecodingMode::Auto;
  /// slicecapd.conf refuse_broken_decoding: a sweep run whose decoding the DecodingWatch shows
  /// broken has its slice's samples set aside as it ends (SessionManager::refuseSweep).
  bool refuseBrokenDecoding = true;
  /// Frames waiting for the recorder's writer at most; more are dropped from the recording.
  std::size_t recordQueueFrames = 4;
  /// The Raspberry Pi tuning file chosen before the camera opened (libcamera cameras; none for
  /// the others): every status shows it.
  std::optional<control::TuningFileView> tuningFile;
  /// What the configuration still does wrong for a real capture (configWarnings): every status
  /// shows them, as does what the camera last adjusted of its configuration.
  std::vector<std::string> warnings;
  /// The control socket's client limits: count, idle timeout, the group allowed to connect.
  ServerLimits clientLimits;
  /// How often a camera without a ready descriptor (the file camera) is asked for a frame.
  std::chrono::microseconds filePollInterval = std::chrono::milliseconds(2);
};

}  // namespace slicecap::daemon
