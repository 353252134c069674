// slicecapd's devices from their description (device_description.hpp): the camera factory and
// the LED, shared by the daemon (daemon_parts.hpp) and `--check-hardware` so that both open
// exactly the same camera.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "slicecap/core/slice.hpp"
#include "slicecap/daemon/config.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/rig/device_description.hpp"

namespace slicecap::rig {

/// The recordings a file camera plays, by slice.
using RecordingsBySlice = std::map<SliceId, std::pair<std::filesystem::path, io::Recording>>;

/// \brief The configured recording itself, or those of a session folder (as `slicecap simulate
/// --session` writes). Throws RigError naming the folder when none is found.
RecordingsBySlice findRecordings(const std::filesystem::path& configured);

/// \brief What the configuration's camera setting builds.
struct CameraSources {
  std::function<std::shared_ptr<hal::Camera>(const SliceId&)> cameraFor;
  std::function<Rig(const SliceId&)> rigFor;
  SliceId firstSlice;  ///< a slice to open the camera for outside a sweep (--check-hardware)
};

/// \brief How the model camera's scene behaves.
enum class ModelScene {
  Sweep,  ///< the virtual rig goes round the slice (the daemon's sessions)
  Still,  ///< the target held still under the camera at the sweep's first position (the check)
};

/// \brief The camera factory of `devices`. camera = model shares `modelLight` (the LED's light,
/// which openLed records) and `clock`, which must outlive every camera; with `modelRealTime`
/// false the model runs on `clock` as a FakeClock that its frames advance (as fast as it
/// renders). Throws what the backends throw when a file the description names cannot be read
/// (a recording, a material) or a device cannot be opened.
CameraSources makeCameraSources(const DeviceDescription& devices, hal::Clock& clock,
                                std::shared_ptr<hal::LedTimeline> modelLight, ModelScene scene,
                                bool modelRealTime = true);

/// \brief The devices `config` asks for that this build does not have (SLICECAP_WITH_*): one
/// line each, "camera = libcamera: libcamera: not in this build (...)"; empty when none.
std::vector<std::string> backendsNotBuilt(const daemon::DaemonConfig& config);

/// \brief The described LED: the GPIO line, or its file LED (its log) which for the model also
/// records its light on `modelLight` a little after each switch. Throws hal::DeviceError (or the
/// GPIO's error) naming the chip, line or file.
std::unique_ptr<hal::Led> openLed(const LedDescription& led, hal::Clock& clock,
                                  std::shared_ptr<hal::LedTimeline> modelLight = nullptr);

}  // namespace slicecap::rig
