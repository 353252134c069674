// The sweep's devices following the session: the camera opened at a sweep's start (configured,
// started, its metering begun, the LED lit), stopped at its pause or stop, and the status's parts.
#include "sweep_devices.hpp"

#include <sys/epoll.h>

#include <iostream>

namespace slicecap::daemon {
namespace {

/// A camera stopped on the way out of a failure or a sweep: its own error is logged, not thrown.
void stopQuietly(hal::Camera& camera) noexcept {
  try {
    camera.stop();
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: stopping the camera: " << error.what() << "\n";
  }
}

}  // namespace

SweepDevices::SweepDevices(DaemonParts& parts, EventLoop& loop, SessionManager& manager,
                           hal::Clock& clock, std::shared_ptr<hal::LedTimeline> commanded)
    : parts_(parts),
      loop_(loop),
      manager_(manager),
      outputs_(parts, manager),
      calibration_(parts),
      strobe_(loop, *parts.led, std::move(commanded), clock, parts.strobe,
              {.switchedOn = [this] { if (camera_) hdr_.pairStarted(*camera_); },
               .failed =
                   [this](const std::string& error) {
                     manager_.pauseSweep("LED error: " + error);
                     reconcile();
                   }}),
      hdr_(parts.hdrLevels) {}

SweepDevices::~SweepDevices() {
  stopCamera();
}

void SweepDevices::ledOff() noexcept {
  try {
    parts_.led->set(false);
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: cannot switch the LED off: " << error.what() << "\n";
  }
}

void SweepDevices::reconcile() {
  const auto wantedSlice = [this] {
    return manager_.capturing() ? manager_.sweepSlice() : std::optional<SliceId>();
  };
  // A run that ends is judged before its texture closes (a stopped sweep's texture closes here):
  // a refusal sets aside the run's texture frames with its samples.
  if (cameraSlice_ && cameraSlice_ != wantedSlice()) stopCamera();
  outputs_.reconcileTexture();  // may pause the sweep: a texture that cannot be opened
  const std::optional<SliceId> wanted = wantedSlice();
  if (cameraSlice_ && cameraSlice_ != wanted) stopCamera();
  if (wanted && !cameraSlice_) startCamera(*wanted);
  if (!manager_.capturing()) ledOff();
  outputs_.reconcileRecorder(cameraSlice_);
}

void SweepDevices::stopCamera() {
  recordDecodingCheck();
  // The run is judged as it ends: refused, or kept (the earlier texture frames it replaced go).
  // Only a run with a live camera is judged: a stop without one (SIGTERM while paused) would
  // otherwise keep whatever run the texture last had open, possibly a refused one.
  if (cameraSlice_ && !refuseBrokenDecoding()) outputs_.keepTextureRun();
  strobe_.stop();
  hdr_.stop();
  if (watchedFd_) loop_.unwatch(*watchedFd_);
  if (pollTimer_) loop_.cancelTimer(*pollTimer_);
  watchedFd_.reset();
  pollTimer_.reset();
  if (camera_) stopQuietly(*camera_);
  camera_.reset();
  calibration_.cameraStopped();
  cameraSlice_.reset();
  processor_ = nullptr;
  ledOff();
}

// The rig's camera for `slice`, configured and started; false (the sweep paused, naming the
// camera) when it cannot be.
bool SweepDevices::openCamera(const SliceId& slice, std::shared_ptr<hal::Camera>& opened) {
  try {
    opened = parts_.rig->camera(slice);
    hal::CameraConfig config = parts_.cameraConfig;
    const hal::ConfigResult result = opened->configure(config);
    if (result.status == hal::ConfigResult::Status::Invalid) {
      manager_.pauseSweep("camera error: " + opened->id() + ": " + result.reason);
      return false;
    }
    // What the camera could not do as configured (e.g. no manual exposure) decides whether
    // the sweep's frames are comparable: the journal and the status say it.
    cameraAdjustment_.clear();
    if (result.status == hal::ConfigResult::Status::Adjusted) {
      cameraAdjustment_ = "camera " + opened->id() + " adjusted the configuration: " + result.reason;
      std::cerr << "slicecapd: " << cameraAdjustment_ << "\n";
    }
    opened->start();
    return true;
  } catch (const std::exception& error) {
    manager_.pauseSweep(std::string("camera error: ") + error.what());
    return false;
  }
}

void SweepDevices::startCamera(const SliceId& slice) {
  // The last sweep's exposure line is not this one's, whatever happens below.
  calibration_.reset();
  hdr_.reset();
  roomLight_.reset();
  decodingCheck_.reset();
  // The run's samples and texture frames start here: a refusal sets aside these alone.
  runFirstRecord_ = manager_.nextRecordNumber();
  runRefused_ = false;
  outputs_.beginTextureRun();
  std::shared_ptr<hal::Camera> opened;
  if (!openCamera(slice, opened)) {
    ledOff();
    return;
  }
  try {
    calibration_.begin(*opened);
  } catch (const std::exception& error) {
    // The camera runs: stopped here, or (one camera serves every slice) the next sweep's
    // configure would find it streaming. The lock or the LED failed; each names its device.
    stopQuietly(*opened);
    calibration_.abandonMetering();
    manager_.pauseSweep(std::string("exposure metering: ") + error.what());
    ledOff();
    return;
  }
  // A live camera's strobe starts lit, before its first frame is exposed: a switch while the
  // first frames expose would cost them.
  if (opened->readyDescriptor() && !calibration_.metering()) {
    try {
      parts_.led->set(true);
    } catch (const std::exception& error) {
      stopQuietly(*opened);
      manager_.pauseSweep(std::string("LED error: ") + error.what());
      ledOff();
      return;
    }
  }
  camera_ = std::move(opened);
  cameraSlice_ = slice;
  observer_ = outputs_.textureObserver();
  processor_ = parts_.rig->pipeline(slice, observer_, std::nullopt);
  watchCamera();
}

// A live camera's frames wake the loop; the file camera is asked at the poll interval.
void SweepDevices::watchCamera() {
  if (const std::optional<int> fd = camera_->readyDescriptor()) {
    watchedFd_ = *fd;
    loop_.watch(*fd, EPOLLIN, [this](std::uint32_t) { pumpFrame(); });
  } else {
    pollTimer_ = loop_.addTimer(parts_.filePollInterval, true, [this] { pumpFrame(); });
  }
}

void SweepDevices::describe(control::StatusView& status) const {
  status.recording = outputs_.recordingView();
  status.texture = outputs_.textureView();
  status.warnings.insert(status.warnings.end(), parts_.warnings.begin(), parts_.warnings.end());
  if (!cameraAdjustment_.empty()) status.warnings.push_back(cameraAdjustment_);
  calibration_.describeExposure(status);
  hdr_.describe(status);
  strobe_.describe(status);
  calibration_.describeDecoding(status);
  if (const control::RoomLightView room = roomLight_.view(); room.toLed || room.change) {
    status.roomLight = room;
    for (std::string& warning : roomLight_.warnings()) status.warnings.push_back(std::move(warning));
  }
  if (control::DecodingCheckView check = decodingCheck_.view();
      check.blackReading || check.windowAtBlack || check.windowUnlit) {
    // Refused only where refuseBrokenDecoding can: a run begun with a session (its first record);
    // once refused (the sweep paused until it is done again), said as done.
    const RefusalPolicy policy = !parts_.refuseBrokenDecoding ? RefusalPolicy::WarnOnly
                                 : runRefused_                ? RefusalPolicy::Refused
                                 : runFirstRecord_            ? RefusalPolicy::Refuse
                                                              : RefusalPolicy::NoSession;
    check.windowUnlitVerdict = decodingCheck_.unlitVerdict(policy);
    status.decodingCheck = check;
    for (std::string& warning : decodingCheck_.warnings())
      status.warnings.push_back(std::move(warning));
  }
  status.tuningFile = parts_.tuningFile;
}

}  // namespace slicecap::daemon
