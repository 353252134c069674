// slicecapd's start-up: every device and file the configuration names is opened here, so a
// mistake stops the start with a message before systemd hears READY.
#include "slicecapd_setup.hpp"

#include "check_hardware_command.hpp"
#include "rpi_tuning_setup.hpp"
#include "slicecapd_devices.hpp"

#include <grp.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <ostream>

#include "slicecap/btf/texture_capture.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/material_export/session_material.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/daemon/config.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/daemon.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/file_camera.hpp"
#include "slicecap/hal/file_led.hpp"
#include "slicecap/hal/gpiod_led.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/hal/libcamera_camera.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/hal/v4l2_camera.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/methods/methods.hpp"
#include "slicecap/prior/isotropy_test.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/render/sheets.hpp"
#include "slicecap/sim/material.hpp"
#include "slicecap/sim/renderer.hpp"
#include "slicecap/sim/rig_scene.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::slicecapd {
namespace {

namespace fs = std::filesystem;
using daemon::DaemonConfig;

constexpr const char* kUsage =
    "usage: slicecapd [--config FILE] [--print-config | --check-config | --led-off]\n"
    "       slicecapd [--config FILE] --check-hardware [--seconds N] [--write-config FILE\n"
    "                 [--overwrite]] [--json]\n"
    "  --config FILE    the configuration (default /etc/slicecap/slicecapd.conf)\n"
    "  --print-config   print the default configuration, every key documented, and exit\n"
    "  --check-config   read and check the configuration, open nothing, and exit\n"
    "  --led-off        switch the LED off and exit (the service's ExecStopPost)\n"
    "  --check-hardware measure the camera and LED with the target under the camera and print\n"
    "                   a report and the configuration lines it supports (the daemon must be\n"
    "                   stopped); --seconds N of frame timing (default 2), --write-config FILE\n"
    "                   writes the lines (an existing FILE only with --overwrite), --json\n"
    "  --version        print the version and exit\n";

struct Options {
  fs::path config = "/etc/slicecap/slicecapd.conf";
  bool printConfig = false, checkConfig = false, ledOff = false, version = false, help = false;
  bool checkHardware = false;
  CheckHardwareOptions hardware;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Options parseOptions(std::span<const std::string> args) {
  Options options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--config") {
      if (i + 1 >= args.size()) throw UsageError("--config needs a FILE");
      options.config = args[++i];
    } else if (arg == "--print-config") {
      options.printConfig = true;
    } else if (arg == "--check-config") {
      options.checkConfig = true;
    } else if (arg == "--led-off") {
      options.ledOff = true;
    } else if (arg == "--check-hardware") {
      options.checkHardware = true;
    } else if (arg == "--seconds") {
      if (i + 1 >= args.size()) throw UsageError("--seconds needs a number");
      char* end = nullptr;
      const std::string& value = args[++i];
      options.hardware.seconds = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !(options.hardware.seconds >= 0.2 && options.hardware.seconds <= 60))
        throw UsageError("--seconds '" + value + "' is not a number of seconds in 0.2..60");
    } else if (arg == "--write-config") {
      if (i + 1 >= args.size()) throw UsageError("--write-config needs a FILE");
      options.hardware.writeConfig = args[++i];
    } else if (arg == "--overwrite") {
      options.hardware.overwrite = true;
    } else if (arg == "--json") {
      options.hardware.json = true;
    } else if (arg == "--version") {
      options.version = true;
    } else if (arg == "--help" || arg == "-h") {
      options.help = true;
    } else {
      throw UsageError("unknown argument '" + arg + "'");
    }
  }
  const bool hardwareOnly = options.hardware.writeConfig || options.hardware.overwrite ||
                            options.hardware.json || options.hardware.seconds != 2.0;
  if (hardwareOnly && !options.checkHardware)
    throw UsageError("--seconds, --write-config, --overwrite and --json go with --check-hardware");
  if (options.hardware.overwrite && !options.hardware.writeConfig)
    throw UsageError("--overwrite goes with --write-config FILE");
  return options;
}

/// The daemon's texture seam on a TextureStore in the session's folder (lib/btf).
class StoreTextureSink final : public daemon::TextureSink {
 public:
  StoreTextureSink(const fs::path& directory, const SliceId& slice,
                   const vision::CameraModel& camera, const btf::TextureStoreLayout& layout)
      : sweep_(directory, slice, camera, layout) {
    // What opening mended after a crash goes to the journal (stderr under systemd).
    const btf::TextureStoreRecovery& recovery = sweep_.store().recovery();
    for (const std::string& dropped : recovery.droppedFiles)
      std::cerr << "slicecapd: texture: removed a damaged frame: " << dropped << "\n";
    if (recovery.leftovers > 0)
      std::cerr << "slicecapd: texture: removed " << recovery.leftovers << " leftovers of an "
                << "interrupted write or redo in " << directory.string() << "\n";
  }

  void add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
           const std::vector<capture::AmbientTerm>& ambient) override {
    sweep_.add(frame, outcome, ambient);
  }
  nlohmann::json status() const override {
    const btf::TextureStore& store = sweep_.store();
    return {{"directory", store.directory().string()},
            {"resolution", store.layout().resolution},
            {"bins_filled", store.filledBins(sweep_.slice())},
            {"frames_stored", store.frameCount(sweep_.slice())},
            {"session_frames_stored", store.frameCount()},
            {"stored_mb", static_cast<double>(store.storedBytes()) / 1e6},
            {"damaged_frames_removed", store.recovery().droppedFiles.size()}};
  }

 private:
  btf::TextureSweep sweep_;
};

// The registry decides the form (isotropic for a session without axial sweeps), so the table
// and the `slicecap:method` the daemon writes beside it agree (methods::runForSession).
Abrdf reconstruct(const SliceSet& slices, const std::string& method) {
  return methods::runForSession(methods::methodNamed(method), slices).table;
}

daemon::IsotropyAssessment assessIsotropy(const SliceSet& slices) {
  const prior::IsotropyVerdict verdict = prior::testIsotropy(slices, prior::defaultPriorModel());
  return {verdict.isotropic, verdict.informative, verdict.reason};
}

void preview(const Abrdf& table, const fs::path& png) {
  char line[96];
  std::snprintf(line, sizeof line, "normalised to max f cos = %.4g 1/sr",
                eval::cosWeightedMaximum(table));
  io::writePng(png, render::previewSheet(png.stem().string(), {line}, table).toPng());
}

// The exported table's fitted material (docs/material-fit.md, docs/material-export.md).
daemon::ExportedMaterial fittedMaterial(const Abrdf& table, const std::string& tableName) {
  material_export::SessionMaterial fitted = material_export::sessionMaterial(table, tableName);
  daemon::ExportedMaterial exported;
  exported.summary = fitted.summary;
  for (material_export::MaterialFile& file : fitted.files)
    exported.files.push_back({std::move(file.suffix), std::move(file.write)});
  return exported;
}

// What a start would find wrong before it opens a device: the files the configuration names, the
// socket's path and group (--check-config opens no device, so a camera or GPIO line is not tried).
std::vector<std::string> startProblems(const DaemonConfig& config) {
  std::vector<std::string> problems;
  const auto check = [&problems](const std::function<void()>& what) {
    try {
      what();
    } catch (const std::exception& error) {
      problems.emplace_back(error.what());
    }
  };
  for (std::string& missing : backendsNotBuilt(config)) problems.push_back(std::move(missing));
  if (const auto problem = daemon::socketPathProblem(config.socket))
    problems.push_back("socket: " + *problem);
  if (!config.socketGroup.empty() && !::getgrnam(config.socketGroup.c_str()))
    problems.push_back("socket_group: group " + config.socketGroup +
                       " does not exist (add it, e.g. with systemd-sysusers and the package's "
                       "slicecap.sysusers, or leave socket_group empty)");
  if (config.camera == DaemonConfig::CameraKind::File)
    check([&] { findRecordings(config.recording); });
  if (config.camera == DaemonConfig::CameraKind::Model)
    check([&] { sim::loadMaterial(config.modelMaterial); });
  if (config.target != "default") check([&] { io::readTargetJson(config.target); });
  if (!config.calibration.empty())
    check([&] {
      io::cameraFromJson(io::readJsonFile(config.calibration), config.calibration.string(), "");
    });
  // A named tuning file is checked whatever the camera: bad input is said, not kept for later.
  if (config.tuningFile.kind == hal::TuningFileSetting::Kind::Path)
    check([&] { hal::validateTuningFile(config.tuningFile.path, std::nullopt); });
  std::error_code error;
  if (fs::exists(config.storage, error) && !fs::is_directory(config.storage, error))
    problems.push_back("storage: " + config.storage.string() + " is not a folder");
  return problems;
}

// The LED and how the strobe drives it, and what the camera is asked for.
void setLedAndCamera(daemon::DaemonParts& parts, const DaemonConfig& config, hal::SteadyClock& clock,
                     const std::shared_ptr<hal::LedTimeline>& modelLight) {
  parts.led = openLed(config, clock, modelLight);
  parts.ledAlternate = config.ledAlternate;
  parts.hdrLevels = config.hdrLevels;
  parts.strobe.framesPerState = config.ledFramesPerState;
  parts.strobe.guardUs = config.ledGuardUs;
  parts.strobe.readoutUs = config.readoutUs;
  parts.cameraConfig = cameraConfigFrom(config);
}

// The frame pipeline of each slice (with its decoding) and the subject of its exposure bracket.
void setFrameProcessing(daemon::DaemonParts& parts, const DaemonConfig& config,
                        const std::function<Rig(const SliceId&)>& rigFor) {
  capture::PipelineSettings pipelineSettings;
  // Without alternation there is no LED-off frame to measure the room light with.
  pipelineSettings.requireAmbient = config.ledAlternate;
  pipelineSettings.noise = {config.sensorReadNoise, config.sensorFullWellElectrons};
  // The offline default's room-light term (processRecording): each LED-on frame waits for the
  // LED-off frame after it (capture::makeLiveFramePipeline) and takes the room light from both
  // sides, each LED-off frame read at its own pose, so a session's recordings processed by
  // `slicecap capture-offline` give the live samples. One side alone is biased along a sweep
  // (a specular material's reflection of the room changes) and by a flicker the frame duration
  // does not hide.
  pipelineSettings.poseAmbientFrames = config.ledAlternate;
  // decoding (issue 27): a live camera's bracket is fitted against the slice's target and camera
  // model, and the sweep's pipeline then reads 8-bit frames through the measured curve; until
  // then (and without one) frames are read as sRGB.
  parts.newDecodingFrameProcessor = [rigFor, pipelineSettings](
                                        const SliceId& slice, capture::FrameObserver observer,
                                        const std::optional<ToneCurve>& curve) {
    const Rig rig = rigFor(slice);
    capture::PipelineSettings settings = pipelineSettings;
    settings.toneCurve = curve;
    return capture::makeLiveFramePipeline(rig.target, rig.camera, settings, std::move(observer));
  };
  parts.newFrameProcessor = [decodingProcessor = parts.newDecodingFrameProcessor](
                                const SliceId& slice, capture::FrameObserver observer) {
    return decodingProcessor(slice, std::move(observer), std::nullopt);
  };
  parts.decoding = daemon::decodingModeFromString(config.decoding);
  parts.bracketSubjectFor = [rigFor](const SliceId& slice) {
    const Rig rig = rigFor(slice);
    return daemon::BracketSubject{rig.target, rig.camera};
  };
}

// What a session keeps besides its samples: recorded frames, the texture, and the exports.
void setSessionOutputs(daemon::DaemonParts& parts, const DaemonConfig& config,
                       const std::function<Rig(const SliceId&)>& rigFor,
                       const std::string& createdBy) {
  if (config.recordFrames) {
    parts.recordingHeaderFor = [rigFor, createdBy](const SliceId& slice) {
      const Rig rig = rigFor(slice);
      io::Recording header;
      header.createdBy = createdBy;
      header.camera = rig.camera;
      header.target = rig.target;
      return header;
    };
  }
  if (config.textureResolution > 0) {
    const int resolution = config.textureResolution, framesPerBin = config.textureFramesPerBin;
    parts.newTextureSink = [rigFor, resolution, framesPerBin](const SliceId& slice,
                                                             const fs::path& session) {
      const Rig rig = rigFor(slice);
      return std::make_unique<StoreTextureSink>(
          session / daemon::kTextureFolder, slice, rig.camera,
          btf::TextureStoreLayout{resolution, rig.target.window, framesPerBin});
    };
  }
  parts.reconstruct = reconstruct;
  parts.preview = preview;
  parts.isotropy = assessIsotropy;
  parts.material = fittedMaterial;
}

// `warnings`: configWarnings(config), already logged; every status shows them.
int serve(const DaemonConfig& config, std::vector<std::string> warnings, std::ostream& err) {
  // Before the camera: libcamera starts its threads in the camera's constructor, and a SIGTERM
  // that reached one of them would end the process without stopping the sweep cleanly.
  daemon::blockSignalsInThisAndLaterThreads(daemon::stopSignals());
  // Before the camera opens: libcamera reads the tuning file when its camera manager starts.
  if (const std::string tuning = applyRpiTuningFile(config); !tuning.empty())
    err << "slicecapd: " << tuning << "\n";
  static hal::SteadyClock clock;
  daemon::DaemonParts parts;
  parts.storage = config.storage;
  parts.clock = &clock;
  auto modelLight = std::make_shared<hal::LedTimeline>();
  setLedAndCamera(parts, config, clock, modelLight);
  parts.warnings = std::move(warnings);

  const Rig configured = configuredRig(config);
  const CameraSources sources = makeCameraSources(config, clock, modelLight, configured.target,
                                                  configured.camera, ModelScene::Sweep);
  parts.cameraFor = sources.cameraFor;
  const std::function<Rig(const SliceId&)> rigFor = sources.rigFor;
  std::string createdBy = std::string("slicecapd ") + kVersion;
  if (config.camera == DaemonConfig::CameraKind::Model ||
      config.camera == DaemonConfig::CameraKind::File)
    createdBy += " (" + sources.kind + ")";
  setFrameProcessing(parts, config, rigFor);
  setSessionOutputs(parts, config, rigFor, createdBy);

  // Outlives the daemon: its socket file is removed when the daemon has stopped (not systemd's).
  const daemon::ListenSocket listening(
      {config.socket, 0660,
       config.socketGroup.empty() ? std::nullopt : std::optional<std::string>(config.socketGroup)});
  parts.clientLimits.idleTimeout = std::chrono::seconds(config.clientIdleTimeoutS);
  parts.clientLimits.socketGroup = listening.group();
  daemon::Daemon daemon(std::move(parts), listening.fd());
  err << "slicecapd " << kVersion << ": serving "
      << (listening.fromSystemd() ? std::string("the socket systemd passed")
                                  : config.socket.string())
      << ", sessions in " << config.storage.string() << "\n";
  daemon.run();
  return 0;
}

}  // namespace

int run(std::span<const std::string> args, std::ostream& out, std::ostream& err) {
  Options options;
  try {
    options = parseOptions(args);
  } catch (const UsageError& error) {
    err << "slicecapd: " << error.what() << "\n" << kUsage;
    return 2;
  }
  if (options.help) {
    out << kUsage;
    return 0;
  }
  if (options.version) {
    out << "slicecapd " << kVersion << "\n";
    return 0;
  }
  if (options.printConfig) {
    out << DaemonConfig::documentedDefaults();
    return 0;
  }
  try {
    const DaemonConfig config = daemon::readDaemonConfig(options.config);
    std::vector<std::string> warnings = daemon::configWarnings(config);
    for (const std::string& warning : warnings)
      err << "slicecapd: " << options.config.string() << ": warning: " << warning << "\n";
    if (options.checkConfig) {
      const std::vector<std::string> problems = startProblems(config);
      for (const std::string& problem : problems)
        err << "slicecapd: " << options.config.string() << ": " << problem << "\n";
      if (!problems.empty()) return 1;
      out << options.config.string() << ": ok\n";
      return 0;
    }
    if (options.checkHardware) return checkHardware(config, options.hardware, out, err);
    if (options.ledOff) {
      hal::SteadyClock clock;
      openLed(config, clock)->set(false);
      return 0;
    }
    return serve(config, std::move(warnings), err);
  } catch (const std::exception& error) {
    err << "slicecapd: " << error.what() << "\n";
    return 1;
  }
}

}  // namespace slicecap::slicecapd
