// The sweep-start metering: measure the brightest pixels, scale the exposure towards the target.
#include "slicecap/daemon/exposure_meter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "slicecap/capture/linear_view.hpp"

namespace slicecap::daemon {

double brightLevel(const hal::Frame& frame, double brightFraction) {
  const Image& image = frame.image;
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0) return 0.0;
  const capture::LinearView view(frame);
  // Every second pixel each way: a highlight of a few pixels still counts, at a quarter the work.
  std::vector<double> levels;
  levels.reserve(std::size_t((image.width + 1) / 2) * std::size_t((image.height + 1) / 2));
  bool ignored = false;
  const int colourChannels = image.channels >= 3 ? 3 : 1;
  for (int y = 0; y < image.height; y += 2) {
    for (int x = 0; x < image.width; x += 2) {
      double largest = 0.0;
      for (int c = 0; c < colourChannels; ++c)
        largest = std::max(largest, view.linear(x, y, c, 2.0, &ignored));
      levels.push_back(largest);
    }
  }
  const auto rank = static_cast<std::ptrdiff_t>(
      std::ceil((1.0 - std::clamp(brightFraction, 0.0, 1.0)) * double(levels.size() - 1)));
  std::nth_element(levels.begin(), levels.begin() + rank, levels.end());
  return levels[std::size_t(rank)];
}

ExposureMeter::ExposureMeter(ExposureMeterParams params) : params_(params) {}

hal::ExposureSetting ExposureMeter::firstSetting(std::optional<double> gain) const {
  return {params_.startExposureUs, gain};
}

void ExposureMeter::accepted(const hal::ExposureSetting& setting) {
  // A step the camera clamped, or rounded, to where it already was: its range or its resolution
  // ends there.
  if (steps_ > 0 && std::abs(setting.exposureUs - current_.exposureUs) < 1e-9 &&
      setting.gain == current_.gain) {
    done_ = true;
    offTargetReason_ = "the camera's exposure range or resolution ended the metering";
  }
  current_ = setting;
  framesSinceChange_ = 0;
  ++locksAccepted_;
}

void ExposureMeter::refused(const std::string& reason) {
  done_ = true;
  onTarget_ = false;
  offTargetReason_ = "the camera refused the next step (" + reason + ")";
}

namespace {

// Whether a frame was taken at the accepted setting: after the last lock reached the camera (its
// request carried it, or the V4L2 driver no longer held frames from before it: an auto exposure
// may report the locked value by chance, with another gain and the LED still off), and reporting
// its exposure. libcamera reports each frame's own, quantised to the sensor's line time (tens of
// microseconds); a frame at the setting before differs by at least the smallest step the metering
// makes (x1.25).
bool takenAt(const hal::Frame& frame, double exposureUs, std::uint32_t locks) {
  if (frame.metadata.exposureLocks < locks) return false;
  const double tolerance = std::max(0.05 * exposureUs, std::min(60.0, 0.5 * exposureUs));
  return std::abs(frame.metadata.exposureUs - exposureUs) <= tolerance;
}

}  // namespace

ExposureMeter::Step ExposureMeter::onFrame(const hal::Frame& frame) {
  if (done_) return {Step::Kind::Done, current_};
  ++framesSinceChange_;
  if (!takenAt(frame, current_.exposureUs, locksAccepted_)) {
    if (framesSinceChange_ < params_.maxFramesPerChange) return {Step::Kind::Wait, current_};
    done_ = true;
    onTarget_ = false;
    char reason[160];
    std::snprintf(reason, sizeof reason,
                  "the camera's frames still reported %.0f us %d frames after the change",
                  frame.metadata.exposureUs, framesSinceChange_);
    offTargetReason_ = reason;
    return {Step::Kind::Done, current_};
  }
  if (framesSinceChange_ <= params_.settleFrames) return {Step::Kind::Wait, current_};
  lastLevel_ = brightLevel(frame, params_.brightFraction);
  measured_ = true;
  const double ratio = params_.targetLevel / std::max(lastLevel_, 1e-6);
  onTarget_ = ratio <= params_.tolerance && ratio >= 1.0 / params_.tolerance;
  if (onTarget_ || steps_ >= params_.maxSteps) {
    done_ = true;
    if (!onTarget_) offTargetReason_ = "the step limit ended the metering";
    return {Step::Kind::Done, current_};
  }
  // A clipped frame says only "too bright": a big step down. Otherwise linear in exposure, at most
  // 3 stops a step, and never beyond the exposure limit.
  const double factor = lastLevel_ >= 0.98 ? 0.25 : std::clamp(ratio, 0.125, 8.0);
  const double nextUs = std::min(current_.exposureUs * factor, params_.maxExposureUs);
  if (nextUs <= current_.exposureUs && factor > 1.0) {
    done_ = true;
    char reason[160];
    std::snprintf(reason, sizeof reason,
                  "the exposure limit (%.0f us: one frame at 30 fps) ended the metering; more "
                  "light or a higher gain is needed",
                  params_.maxExposureUs);
    offTargetReason_ = reason;
    return {Step::Kind::Done, current_};
  }
  ++steps_;
  return {Step::Kind::Lock, {nextUs, current_.gain}};
}

std::string ExposureMeter::summary() const {
  char line[320];
  char level[64] = "not measured";
  if (measured_) std::snprintf(level, sizeof level, "at %.2f of full scale", lastLevel_);
  std::snprintf(line, sizeof line,
                "exposure locked at %.0f us, gain %g: the brightest pixels %s (target %.2f) "
                "after %d step%s",
                current_.exposureUs, current_.gain.value_or(1.0), level, params_.targetLevel,
                steps_, steps_ == 1 ? "" : "s");
  if (onTarget_) return line;
  return std::string(line) + "; off the target: " +
         (offTargetReason_.empty() ? std::string("the metering ended early") : offTargetReason_);
}

}  // namespace slicecap::daemon
