// The Raspberry Pi tuning file of the processed path, set before libcamera's one CameraManager
// starts (slicecapd.conf tuning_file; hal::chooseTuningFile decides, this applies it).
#pragma once

#include <optional>
#include <string>

#include "slicecap/control/reply_views.hpp"
#include "slicecap/daemon/config.hpp"

namespace slicecap::rig {

/// \brief Checks a tuning file named in the configuration (whatever the camera), then, with
/// camera = libcamera, asks the camera (through a CameraManager started and stopped here, before
/// the daemon's own) whether RAW will be granted and which sensor it is, and sets
/// LIBCAMERA_RPI_TUNING_FILE to the chosen file. The Pi's IPA
/// reads that variable when the next CameraManager matches the camera (Raspberry Pi's libcamera
/// fork: pipeline_base.cpp CameraData::loadIPA -> ipa_proxy.cpp ipaConfigurationFile, reached
/// from the pipeline handler's match() in CameraManager::start), so it must be set before the
/// daemon's camera opens, and a camera opened before it keeps the file it had. Returns what was
/// chosen and why, for the log and every status (nullopt for other cameras). Throws hal::CameraError naming the file when it cannot be
/// read or is not a tuning file for this Pi's ISP.
std::optional<control::TuningFileView> applyRpiTuningFile(const daemon::DaemonConfig& config);

}  // namespace slicecap::rig
