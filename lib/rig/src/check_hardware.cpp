// `slicecapd --check-hardware`: the devices from the configuration, the report printed.
#include "slicecap/rig/check_hardware.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <optional>
#include <filesystem>
#include <ostream>

#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/device_backends.hpp"
#include "slicecap/hwcheck/hardware_check.hpp"
#include "slicecap/rig/configured_devices.hpp"
#include "slicecap/rig/device_description.hpp"

namespace slicecap::rig {
namespace {

namespace fs = std::filesystem;
using daemon::DaemonConfig;

// Whether a daemon answers on the control socket: the check must not fight a session for the
// camera and the LED.
bool daemonAnswers(const fs::path& socketPath) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string path = socketPath.string();
  if (path.size() >= sizeof address.sun_path) {
    ::close(fd);
    return false;
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const bool connected = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return connected;
}

// A backend this slicecapd was built without: rebuilding is the remedy, not the wiring.
std::string notBuiltAdvice(const hal::BackendNotBuilt& error) {
  const std::string option = hal::backendOption(error.backend());
  return "build slicecapd with -D" + option + "=ON (docs/guide/install.md), or check the other "
         "devices with camera = model or camera = file";
}

// Whether the check may start: no daemon holds the devices, and the file to write is free.
bool mayStart(const DaemonConfig& config, const CheckHardwareOptions& options, std::ostream& err) {
  if (daemonAnswers(config.socket)) {
    err << "slicecapd: a daemon answers on " << config.socket.string()
        << ": stop it first (systemctl stop slicecapd), the check opens the camera and the LED "
           "itself\n";
    return false;
  }
  // Refused before measuring, not after (writeConfigFile refuses again, atomically).
  std::error_code existsError;
  if (options.writeConfig && !options.overwrite && fs::exists(*options.writeConfig, existsError)) {
    err << "slicecapd: " << *options.writeConfig
        << " exists: not overwritten (pass --overwrite, or choose another file and merge its "
           "lines into slicecapd.conf)\n";
    return false;
  }
  return true;
}

// The described camera of its first slice in `camera` and its rig in `rig`; a failed item in
// `report` when they cannot be opened (`camera` stays as far as it got).
void openCheckCamera(const DeviceDescription& devices, hal::Clock& clock,
                     const std::shared_ptr<hal::LedTimeline>& modelLight, bool simulated,
                     const hwcheck::BackendInfo& backend, hwcheck::HardwareReport& report,
                     std::shared_ptr<hal::Camera>& camera, Rig& rig) {
  try {
    const CameraSources sources = makeCameraSources(devices, clock, modelLight, ModelScene::Still,
                                                    /*modelRealTime=*/!simulated);
    camera = sources.cameraFor(sources.firstSlice);
    rig = sources.rigFor(sources.firstSlice);
  } catch (const hal::BackendNotBuilt& error) {
    report.cameraId = devices.cameraName;
    report.cameras = backend.cameras;
    report.items.push_back({"camera", hwcheck::Verdict::Fail, error.what(), notBuiltAdvice(error)});
  } catch (const std::exception& error) {
    report.cameraId = devices.cameraName;
    report.cameras = backend.cameras;
    report.items.push_back({"camera", hwcheck::Verdict::Fail, std::string("no camera: ") + error.what(),
                            "connect the camera and check camera and camera_device in the "
                            "configuration (with camera = file: camera_recording)"});
  }
}

// The described LED; null, with a failed item in `report`, when it cannot be opened.
std::unique_ptr<hal::Led> openCheckLed(const LedDescription& description, hal::Clock& clock,
                                       const std::shared_ptr<hal::LedTimeline>& modelLight,
                                       const hal::Camera& camera,
                                       const hwcheck::BackendInfo& backend,
                                       hwcheck::HardwareReport& report) {
  try {
    return openLed(description, clock, modelLight);
  } catch (const hal::BackendNotBuilt& error) {
    report.cameraId = camera.id();
    report.cameras = backend.cameras;
    report.items.push_back({"LED", hwcheck::Verdict::Fail, error.what(), notBuiltAdvice(error)});
  } catch (const std::exception& error) {
    report.cameraId = camera.id();
    report.cameras = backend.cameras;
    report.items.push_back({"LED", hwcheck::Verdict::Fail, std::string("no LED: ") + error.what(),
                            "check led_chip, led_line and led_active_low (gpioinfo lists the "
                            "lines), and that the user may use the GPIO chip"});
  }
  return nullptr;
}

// Prints the report and writes its configuration lines when asked; the exit status.
int reportResult(const hwcheck::HardwareReport& report, const CheckHardwareOptions& options,
                 std::ostream& out, std::ostream& err) {
  if (options.json)
    out << report.json().dump(2) << "\n";
  else
    out << report.text();
  if (options.writeConfig) {
    if (report.configLines.empty()) {
      err << "slicecapd: nothing measured to write to " << *options.writeConfig
          << " (see the items above)\n";
      return 1;
    }
    try {
      hwcheck::writeConfigFile(*options.writeConfig, report.configSnippet(), options.overwrite);
      err << "slicecapd: wrote " << *options.writeConfig
          << " (merge its lines into slicecapd.conf)\n";
    } catch (const std::exception& error) {
      err << "slicecapd: " << error.what() << "\n";
      return 1;
    }
  }
  return report.overall() == hwcheck::Verdict::Fail ? 1 : 0;
}

}  // namespace

int checkHardware(const DaemonConfig& config, const CheckHardwareOptions& options,
                  std::ostream& out, std::ostream& err) {
  if (!mayStart(config, options, err)) return 1;
  // camera = model renders every frame in software, slower than 30 fps on a loaded machine: in
  // real time the check would measure the machine's load (frames dropped for want of a free
  // buffer), not the camera it models. The model runs on a simulated clock instead, which its
  // frames advance as a real camera's time would pass; every other camera on the steady clock.
  hal::SteadyClock steadyClock;
  hal::FakeClock simulatedClock(steadyClock.nowUs());
  const bool simulated = config.camera == DaemonConfig::CameraKind::Model;
  hal::Clock& clock = simulated ? static_cast<hal::Clock&>(simulatedClock) : steadyClock;
  const DeviceDescription devices = describeDevices(config);
  auto modelLight = std::make_shared<hal::LedTimeline>();
  const hwcheck::BackendInfo backend = describeBackend(config);

  hwcheck::HardwareReport report;
  std::shared_ptr<hal::Camera> camera;
  Rig rig = devices.rig;
  openCheckCamera(devices, clock, modelLight, simulated, backend, report, camera, rig);
  std::unique_ptr<hal::Led> led;
  if (camera) led = openCheckLed(devices.led, clock, modelLight, *camera, backend, report);
  if (camera && led) {
    // The check locks the exposures it measures with itself: the sweep's setting is not one.
    hal::CameraConfig cameraConfig = devices.cameraConfig;
    cameraConfig.exposureUs.reset();
    cameraConfig.gain.reset();
    hwcheck::HardwareCheckOptions checkOptions;
    checkOptions.captureSeconds = options.seconds;
    report = hwcheck::runHardwareCheck(*camera, cameraConfig, *led, clock, rig.target, rig.camera,
                                       backend, checkOptions);
  }
  return reportResult(report, options, out, err);
}

}  // namespace slicecap::rig
