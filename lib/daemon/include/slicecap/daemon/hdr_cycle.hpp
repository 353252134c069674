// A live HDR sweep's exposure cycle (docs/method.md 9.3): the levels, which one each LED pair
// takes, the level a frame was taken at, and the shortest level brought down where it clips.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/frame.hpp"

namespace slicecap::daemon {

/// \brief The most exposures an HDR sweep alternates: slicecapd.conf's hdr_levels is read in
/// 1..kMaxHdrLevels (readDaemonConfig, the one place a value from outside is checked; 1: no HDR).
inline constexpr int kMaxHdrLevels = 3;

/// \brief How the cycle starts and adapts. The longest level is the sweep's locked exposure (the
/// metering's, or exposure_us); each shorter one starts `stepRatio` below the one before.
struct HdrCycleParams {
  int levels = 2;  ///< 2..kMaxHdrLevels (slicecapd.conf hdr_levels above 1)
  /// 8-bit frames keep ~6 bits of a value 16 times below the level that holds it: the merge's
  /// noise weights then still prefer the longer level wherever it is not clipped.
  double stepRatio = 16.0;
  /// LED pairs taken at one level before the next: a camera applies a new exposure a few frames
  /// late (the hardware check's exposure-lock delay), so the first pair after a change may be
  /// split across two exposures; every frame is labelled by the exposure it reports, and the
  /// other pairs of the block are whole.
  int pairsPerLevel = 2;
  /// The shortest level is divided by this when its window clips (a highlight brighter than the
  /// start expected), down to minExposureUs.
  double shortenOnClip = 4.0;
  double minExposureUs = 20.0;
};

/// \brief The cycle of one sweep run. Single-threaded (the daemon's event loop).
class HdrCycle {
 public:
  /// \brief Throws SlicecapdError with refusal()'s text when refusal() names one.
  HdrCycle(hal::ExposureSetting longest, HdrCycleParams params = {});

  /// \brief Why no cycle can start from `longest` with `params`, or nullopt: levels outside
  /// 2..kMaxHdrLevels (a caller's error: the configuration refuses those), a step ratio <= 1, a
  /// pair count < 1 or a longest exposure not above minExposureUs (a sweep then takes one
  /// exposure, SweepHdr::start).
  static std::optional<std::string> refusal(const hal::ExposureSetting& longest,
                                            const HdrCycleParams& params);

  /// \brief Each level's exposure now, longest (level 0) first, microseconds.
  const std::vector<double>& levelsUs() const { return levelsUs_; }
  /// \brief A new LED pair starts (the LED switched on): the setting to lock when it starts the
  /// next level's block, else nullopt.
  std::optional<hal::ExposureSetting> pairStarted();
  /// \brief What the camera set for the level's last request (its exposure is then that level's).
  void accepted(int level, const hal::ExposureSetting& setting);
  /// \brief The level a frame was taken at: the one with the exposure, now or before a change,
  /// nearest the frame's reported one (by ratio; frames arrive a few after a change). A frame
  /// that reports none (0) is at the level last requested.
  int levelOf(const hal::FrameMetadata& metadata) const;
  /// \brief An LED-on frame of the shortest level whose window clipped: that level is shortened
  /// (from its next block on) when the frame was taken at its present exposure, not at one a
  /// shortening already replaced (frames arrive a few after the request). Returns whether it
  /// changed.
  bool shortestClipped(const hal::FrameMetadata& metadata);
  /// \brief The level requested last (what pairStarted's setting is for).
  int requestedLevel() const { return level_; }
  /// \brief One line for the status: the levels and any shortening.
  std::string summary() const;

 private:
  hal::ExposureSetting settingOf(int level) const;

  HdrCycleParams params_;
  std::optional<double> gain_;
  std::vector<double> levelsUs_;
  std::vector<std::vector<double>> heldUs_;  // per level, every exposure it has had
  int level_ = 0;          // the level requested last
  int pairsAtLevel_ = 0;   // pairs started at it so far
  int shortenings_ = 0;
};

}  // namespace slicecap::daemon
