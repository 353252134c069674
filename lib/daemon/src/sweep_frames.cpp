// One camera frame through the sweep: the calibration takes it first (metering, bracket), then
// the strobe labels it, the pipeline makes it a sample, and the session, HDR cycle, strobe,
// texture and recording each take their part of the settled outcome.
#include <filesystem>
#include <iostream>

#include "slicecap/io/target_json.hpp"
#include "sweep_devices.hpp"

namespace slicecap::daemon {

void SweepDevices::pumpFrame() {
  if (!camera_ || !cameraSlice_) return;
  hal::CaptureResult result = camera_->nextFrame(std::chrono::milliseconds(0));
  if (result.status == hal::CaptureResult::Status::Timeout) return;
  if (endOfFrames(result)) return;
  hal::Frame& frame = *result.frame;
  if (calibrate(frame)) return;
  if (camera_->readyDescriptor()) hdr_.start(camera_->id(), calibration_.lockedSetting());
  strobe(frame);
  std::vector<capture::SettledFrame> settled;
  try {
    settled = processor_(&frame, *cameraSlice_);
  } catch (const std::exception& error) {
    capture::FrameOutcome outcome;
    outcome.kind = capture::FrameOutcome::Kind::Rejected;
    outcome.rejectReason = capture::RejectReason::BadFrame;
    outcome.detail = error.what();
    settled = {{frame.metadata, std::move(outcome)}};
  }
  for (const capture::SettledFrame& each : settled) apply(each);
  outputs_.pauseOnTextureError();
  strobe_.scheduleSwitch();
  outputs_.record(std::move(frame));
  reconcile();  // a storage error pauses the sweep, and the LED must go off at once
}

// The stream's end or the camera's error: the held frames settle, the sweep pauses (true).
bool SweepDevices::endOfFrames(const hal::CaptureResult& result) {
  if (result.status == hal::CaptureResult::Status::Frame) return false;
  settleHeld();
  if (result.status == hal::CaptureResult::Status::EndOfStream)
    // A recording played to its end, or the virtual rig's operator went round.
    manager_.pauseSweep(camera_->readyDescriptor()
                            ? "the camera's stream has ended (" + camera_->id() + ")"
                            : std::string("the camera's recording has ended"));
  else
    manager_.pauseSweep("camera error: " + result.error);
  reconcile();
  return true;
}

// The sweep start's metering and bracket take the frame (true), or it goes to the pipeline.
bool SweepDevices::calibrate(const hal::Frame& frame) {
  if (calibration_.metering()) {
    try {
      calibration_.meterFrame(*camera_, frame);
    } catch (const std::exception& error) {
      // The camera's lock or the LED failed: each message names its device.
      manager_.pauseSweep(std::string("exposure metering: ") + error.what());
      reconcile();
    }
    return true;
  }
  if (!camera_->readyDescriptor()) return false;
  if (!calibration_.decided() && !calibration_.bracketing())
    if (std::optional<SweepDecoding> decided = calibration_.decide(*camera_, frame, *cameraSlice_))
      applyDecoding(std::move(*decided));
  if (!calibration_.bracketing()) return false;
  try {
    if (std::optional<SweepDecoding> decided = calibration_.bracketFrame(*camera_, frame))
      applyDecoding(std::move(*decided));
  } catch (const std::exception& error) {
    manager_.pauseSweep(std::string("response bracket: ") + error.what());
    reconcile();
  }
  return true;
}

/// The sweep run's decoding: the pipeline reads through it, the status and the session say it,
/// the recording records it (with the bracket frames, under record_frames).
void SweepDevices::applyDecoding(SweepDecoding decided) {
  std::cerr << "slicecapd: camera " << camera_->id() << ": decoding "
            << io::toString(decided.decoding.kind) << ": " << decided.note << "\n";
  if (!decided.warning.empty()) std::cerr << "slicecapd: " << decided.warning << "\n";
  calibration_.noteDecodingWarning(decided.warning);
  std::string decodingWarning = decided.warning;
  if (decided.decoding.kind == io::RecordedDecoding::Kind::MeasuredCurve) {
    // Frames the sRGB pipeline still holds settle there first (none, as the decision comes
    // before any frame is processed; a held frame must never be lost silently).
    settleHeld();
    processor_ = parts_.rig->pipeline(*cameraSlice_, observer_, decided.decoding.curve);
  }
  recordDecoding(decided, decodingWarning);
  outputs_.setDecoding(decided.decoding);
  outputs_.recordBracket(decided, *cameraSlice_);
  decided.bracketFrames.clear();
  calibration_.noteDecodingWarning(decodingWarning);
  calibration_.adopt(std::move(decided));
}

// <session>/decoding/<slice>.json; a failure is added to `warning` (the sweep goes on: its
// samples are what matters; the status shows why the decoding is unrecorded).
void SweepDevices::recordDecoding(const SweepDecoding& decided, std::string& warning) const {
  const std::optional<std::filesystem::path> session = manager_.sessionDirectory();
  if (!session) return;
  try {
    std::filesystem::create_directories(*session / kDecodingFolder);
    io::writeJsonFileAtomically(*session / kDecodingFolder / (folderName(*cameraSlice_) + ".json"),
                                toJson(decided, camera_->id()));
  } catch (const std::exception& error) {
    warning += std::string(warning.empty() ? "" : "; ") +
               "the sweep's decoding could not be recorded in the session: " + error.what();
  }
}

void SweepDevices::recordDecodingCheck() const noexcept {
  if (!cameraSlice_) return;
  const control::DecodingCheckView figures = decodingCheck_.view();
  if (!figures.blackReading && !figures.windowAtBlack && !figures.windowUnlit) return;
  try {
    const std::optional<std::filesystem::path> session = manager_.sessionDirectory();
    const std::filesystem::path file =
        session ? *session / kDecodingFolder / (folderName(*cameraSlice_) + ".json")
                : std::filesystem::path();
    if (session && std::filesystem::exists(file))
      daemon::recordDecodingCheck(file, figures, decodingCheck_.warnings());
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: recording the sweep's decoding check: " << error.what() << "\n";
  }
}

bool SweepDevices::refuseBrokenDecoding() {
  if (!cameraSlice_ || !parts_.refuseBrokenDecoding || !runFirstRecord_) return false;
  const std::optional<std::string> reason = decodingCheck_.refusal();
  if (!reason) return false;
  std::cerr << "slicecapd: sweep " << toString(*cameraSlice_) << " refused: " << *reason << "\n";
  // Once a run: stopCamera clears cameraSlice_, and a new run resets the watch. The run's
  // texture frames go with its samples, and only if those were set aside; the journal names
  // them first, so a crash before they move leaves them to be set aside on the next opening.
  if (!manager_.refuseSweep(*cameraSlice_, *reason, *runFirstRecord_, outputs_.textureRun()))
    return false;
  manager_.addToError(outputs_.setAsideTextureRun());
  runRefused_ = true;
  return true;
}

/// A recorded frame says whether the LED was on, and the LED follows it (its log then shows
/// what a live run would have done). A live frame is labelled by the strobe from the LED's
/// timeline over its rows (a frame queued ahead was exposed frames before it arrives).
void SweepDevices::strobe(hal::Frame& frame) {
  if (!camera_->readyDescriptor()) {
    parts_.led->set(frame.metadata.ledOn);
    return;
  }
  strobe_.label(frame, camera_->id());
  hdr_.label(frame);
}

void SweepDevices::settleHeld() {
  if (!processor_ || !cameraSlice_) return;
  std::vector<capture::SettledFrame> settled;
  try {
    settled = processor_(nullptr, *cameraSlice_);
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: settling the sweep's last frames: " << error.what() << "\n";
  }
  for (const capture::SettledFrame& frame : settled) apply(frame);
}

/// One settled outcome into the session, the HDR cycle, the room light and the strobe's rows.
void SweepDevices::apply(const capture::SettledFrame& settled) {
  const capture::FrameOutcome& outcome = settled.outcome;
  if (outcome.viewElevationErrorDeg)
    manager_.noteViewElevationErrorDeg(*outcome.viewElevationErrorDeg);
  hdr_.noteOutcome(settled.metadata, outcome);
  switch (outcome.kind) {
    case capture::FrameOutcome::Kind::Sample:
      manager_.acceptSample(*outcome.sample);
      break;
    case capture::FrameOutcome::Kind::Rejected:
      manager_.rejectFrame(outcome.rejectReason);
      break;
    case capture::FrameOutcome::Kind::Ambient:
      break;
  }
  roomLight_.note(outcome);
  decodingCheck_.note(outcome, settled.metadata.sequence);
  strobe_.noteRows(outcome.measurement.rowsOfInterest);
}

}  // namespace slicecap::daemon
