// A live sweep run's exposure metering and decoding decision (docs/method.md, linear light).
#include "sweep_calibration.hpp"

#include <iostream>

namespace slicecap::daemon {

void SweepCalibration::reset() {
  meter_.reset();
  exposureNote_.clear();
  exposureUnlocked_ = false;
  bracket_.reset();
  subject_.reset();
  decoding_.reset();
  decodingWarning_.clear();
  locksAccepted_ = 0;
  lockedSetting_.reset();
  if (parts_.cameraConfig.exposureUs)
    lockedSetting_ =
        hal::ExposureSetting{*parts_.cameraConfig.exposureUs, parts_.cameraConfig.gain};
}

void SweepCalibration::begin(hal::Camera& opened) {
  if (parts_.cameraConfig.exposureUs || !opened.readyDescriptor()) return;
  ExposureMeter metering(parts_.exposureMeter);
  const hal::ExposureLock lock =
      opened.lockExposure(metering.firstSetting(parts_.cameraConfig.gain));
  if (!lock.locked) {
    leaveExposureToCamera(opened.id(), lock.reason);
    return;
  }
  metering.accepted(*lock.locked);
  ++locksAccepted_;
  meter_ = metering;
  exposureNote_ = "metering the exposure with the LED on";
  parts_.led->set(true);
}

void SweepCalibration::abandonMetering() {
  meter_.reset();
  exposureNote_.clear();
}

void SweepCalibration::cameraStopped() {
  if (meter_) exposureNote_.clear();
  meter_.reset();
  bracket_.reset();
}

void SweepCalibration::leaveExposureToCamera(const std::string& cameraId,
                                             const std::string& reason) {
  meter_.reset();
  exposureUnlocked_ = true;
  exposureNote_ = "camera " + cameraId + ": exposure not locked (" + reason +
                  "): its auto exposure runs through the sweep";
  std::cerr << "slicecapd: " << exposureNote_ << "\n";
}

void SweepCalibration::meterFrame(hal::Camera& camera, const hal::Frame& frame) {
  parts_.led->set(true);
  const ExposureMeter::Step step = meter_->onFrame(frame);
  if (step.kind == ExposureMeter::Step::Kind::Lock) {
    const hal::ExposureLock lock = camera.lockExposure(step.setting);
    if (lock.locked) {
      meter_->accepted(*lock.locked);
      ++locksAccepted_;
    } else {
      // The setting accepted before stays fixed (a source that refuses part of a lock puts
      // back what it had): the metering ends there, on the next frame.
      meter_->refused(lock.reason);
    }
  } else if (step.kind == ExposureMeter::Step::Kind::Done) {
    exposureNote_ = "camera " + camera.id() + ": " + meter_->summary();
    std::cerr << "slicecapd: " << exposureNote_ << "\n";
    lockedSetting_ = step.setting;
    meter_.reset();
  }
}

std::optional<SweepDecoding> SweepCalibration::decide(hal::Camera& camera, const hal::Frame& frame,
                                                      const SliceId& slice) {
  const std::string id = camera.id();
  if (frame.encoding == PixelEncoding::Linear16 || parts_.decoding == DecodingMode::Srgb)
    return decodingWithoutBracket(frame.encoding, parts_.decoding, id, "");
  const auto fallBack = [&](const std::string& why) {
    return decodingWithoutBracket(frame.encoding, parts_.decoding, id, why);
  };
  subject_ = parts_.rig->bracketSubject(slice);
  if (!subject_)
    return fallBack("this daemon was started without the target and pipeline a response "
                    "bracket needs (decoding = " + toString(parts_.decoding) + ")");
  if (exposureUnlocked_ || !lockedSetting_)
    return fallBack("no response bracket: its exposure is not locked (" + exposureNote_ +
                    "); set exposure_us and gain, or decoding = srgb");
  bracket_.emplace(*lockedSetting_, locksAccepted_, capture::BracketPlan{},
                   parts_.exposureMeter.maxExposureUs);
  const hal::ExposureLock lock = camera.lockExposure(bracket_->firstSetting());
  if (!lock.locked) {
    bracket_->refused(lock.reason);
    return finishBracket(id);
  }
  bracket_->accepted();
  ++locksAccepted_;
  parts_.led->set(true);
  return std::nullopt;
}

std::optional<SweepDecoding> SweepCalibration::bracketFrame(hal::Camera& camera,
                                                            const hal::Frame& frame) {
  parts_.led->set(true);
  const ResponseBracket::Step step = bracket_->onFrame(frame);
  if (step.kind == ResponseBracket::Step::Kind::Lock) {
    const hal::ExposureLock lock = camera.lockExposure(step.setting);
    if (!lock.locked) {
      bracket_->refused(lock.reason);
    } else {
      bracket_->accepted();
      ++locksAccepted_;
    }
  } else if (step.kind == ResponseBracket::Step::Kind::Done) {
    return finishBracket(camera.id());
  }
  return std::nullopt;
}

SweepDecoding SweepCalibration::finishBracket(const std::string& cameraId) {
  ResponseBracket done = std::move(*bracket_);
  bracket_.reset();
  // The fit reads the frames' poses and codes: about a second on a Pi, once a sweep run.
  return decodingFromBracket(std::move(done.frames()), done.failure(),
                             *subject_, cameraId);
}

void SweepCalibration::describeExposure(control::StatusView& status) const {
  // The last sweep start's: a camera that could not lock is a warning, shown once.
  if (exposureUnlocked_)
    status.warnings.push_back(exposureNote_);
  else if (!exposureNote_.empty())
    status.exposure = exposureNote_;
}

void SweepCalibration::describeDecoding(control::StatusView& status) const {
  if (decoding_)
    status.decoding = control::DecodingView{io::toString(decoding_->decoding.kind), decoding_->note};
  else if (bracket_)
    status.decoding =
        control::DecodingView{"measuring", "taking the response bracket with the LED on"};
  if (!decodingWarning_.empty()) status.warnings.push_back(decodingWarning_);
}

}  // namespace slicecap::daemon
