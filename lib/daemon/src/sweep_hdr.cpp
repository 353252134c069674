// A live sweep's HDR between the frame loop and its exposure cycle (docs/method.md 9.3).
#include "sweep_hdr.hpp"

#include <algorithm>
#include <iostream>
#include <optional>
#include <string>

namespace slicecap::daemon {

void SweepHdr::reset() {
  cycle_.reset();
  note_.clear();
}

void SweepHdr::stop() {
  if (cycle_) note_ = cycle_->summary();
  cycle_.reset();
}

void SweepHdr::start(const std::string& cameraId, const std::optional<hal::ExposureSetting>& locked) {
  if (levels_ < 2 || started()) return;
  const auto oneExposure = [this](const std::string& why) {
    note_ = "hdr_levels = " + std::to_string(levels_) + " not used: " + why +
            "; the sweep takes one exposure";
  };
  if (!locked) {
    oneExposure("the sweep's exposure is not locked");
  } else if (const std::optional<std::string> why =
                 HdrCycle::refusal(*locked, HdrCycleParams{.levels = levels_})) {
    oneExposure(*why);  // a locked exposure too short to divide (HdrCycle names it)
  } else {
    cycle_.emplace(*locked, HdrCycleParams{.levels = levels_});
    note_ = cycle_->summary();
  }
  std::cerr << "slicecapd: camera " << cameraId << ": " << note_ << "\n";
}

void SweepHdr::label(hal::Frame& frame) const {
  if (cycle_) frame.metadata.exposureLevel = cycle_->levelOf(frame.metadata);
}

void SweepHdr::pairStarted(hal::Camera& camera) {
  if (!cycle_) return;
  const std::optional<hal::ExposureSetting> wanted = cycle_->pairStarted();
  if (!wanted) return;
  try {
    const hal::ExposureLock lock = camera.lockExposure(*wanted);
    if (lock.locked) {
      cycle_->accepted(cycle_->requestedLevel(), *lock.locked);
      return;
    }
    note_ = "camera " + camera.id() + " refused an HDR exposure (" + lock.reason +
            "): one exposure from here";
  } catch (const std::exception& error) {
    note_ = "camera " + camera.id() + " failed an HDR exposure (" + error.what() +
            "): one exposure from here";
  }
  // The frames already labelled keep their levels; later ones are at the exposure the camera kept.
  std::cerr << "slicecapd: " << note_ << "\n";
  cycle_.reset();
}

void SweepHdr::noteOutcome(const hal::FrameMetadata& frame, const capture::FrameOutcome& outcome) {
  if (!cycle_ || !outcome.sample || !outcome.sample->hdr) return;
  if (frame.exposureLevel != static_cast<int>(cycle_->levelsUs().size()) - 1) return;
  const std::vector<capture::HdrCell>& cells = outcome.sample->hdr->cells;
  if (std::any_of(cells.begin(), cells.end(), [](const capture::HdrCell& c) { return c.clipped; }))
    cycle_->shortestClipped(frame);
}

void SweepHdr::describe(control::StatusView& status) const {
  if (cycle_)
    status.hdr = cycle_->summary();
  else if (!note_.empty())
    status.hdr = note_;
}

}  // namespace slicecap::daemon
