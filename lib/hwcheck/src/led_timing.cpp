// LED timing: switches at spread phases of the frame, the half-lit row of each in the whites.
#include "slicecap/hwcheck/led_timing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {
namespace {

struct Reference {
  std::vector<double> on, off;
  std::vector<bool> usable;  // the LED changes the row's whites by more than 5 %
};

std::vector<double> averageRows(const std::vector<SeenFrame>& frames, const WhiteRows& whites,
                                const capture::CodeTable& codes) {
  std::vector<double> sum(std::size_t(whites.heightPx), 0.0);
  for (const SeenFrame& seen : frames) {
    const std::vector<double> rows = whites.rowMeans(seen.frame, codes);
    for (std::size_t r = 0; r < sum.size(); ++r) sum[r] += rows[r];
  }
  for (double& v : sum) v /= double(std::max<std::size_t>(frames.size(), 1));
  return sum;
}

// Frames whose every row was exposed after the last switch: timestamp at least two periods after
// it (row 0's exposure ends at the timestamp, and a frame's rows take at most a period).
std::vector<SeenFrame> settledFrames(CheckRig& rig, int count, double periodUs) {
  const std::int64_t switchedUs = rig.clock().nowUs();
  std::vector<SeenFrame> frames;
  for (int n = 0; int(frames.size()) < count; ++n) {
    if (n > 10 * count + 10)
      throw HardwareCheckError(rig.camera().id() + ": no settled frames after an LED switch");
    std::optional<SeenFrame> seen = rig.next(std::chrono::milliseconds(1000));
    if (!seen) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
    if (double(seen->frame.metadata.timestampUs - switchedUs) > 2.0 * periodUs)
      frames.push_back(std::move(*seen));
  }
  return frames;
}

// The half-lit row of a frame whose rows went from `fromOn` to the other state, by the area
// under the ramp (exact for a symmetric ramp, robust to noise): nullopt unless the ramp lies
// inside the white rows with settled rows either side.
std::optional<double> halfRow(const std::vector<double>& rows, const Reference& ref, bool toOn,
                              const WhiteRows& whites) {
  // The LED-on fraction of each usable row, interpolated over unusable ones between them.
  std::vector<int> usedRows;
  std::vector<double> fraction;
  for (int r = whites.firstRow; r >= 0 && r <= whites.lastRow; ++r) {
    if (!ref.usable[std::size_t(r)]) continue;
    const double f = (rows[std::size_t(r)] - ref.off[std::size_t(r)]) /
                     (ref.on[std::size_t(r)] - ref.off[std::size_t(r)]);
    usedRows.push_back(r);
    fraction.push_back(toOn ? f : 1.0 - f);  // rising from 0 to 1 either way
  }
  if (usedRows.size() < 16) return std::nullopt;
  const std::size_t edge = 4;  // rows at each end that must be settled
  double headMean = 0.0, tailMean = 0.0;
  for (std::size_t i = 0; i < edge; ++i) {
    headMean += fraction[i] / double(edge);
    tailMean += fraction[fraction.size() - 1 - i] / double(edge);
  }
  if (headMean > 0.1 || tailMean < 0.9) return std::nullopt;  // no ramp, or not inside the whites
  // The ramp's rows (f between 0.1 and 0.9) plus a margin: the integral over only those keeps the
  // noise of the settled rows out of it.
  std::size_t first = fraction.size(), last = 0;
  for (std::size_t i = 0; i < fraction.size(); ++i)
    if (fraction[i] > 0.1 && fraction[i] < 0.9) first = std::min(first, i), last = std::max(last, i);
  if (first > last) {  // a step between two rows: the ramp is narrower than a row
    for (std::size_t i = 0; i + 1 < fraction.size(); ++i)
      if (fraction[i] < 0.5 && fraction[i + 1] >= 0.5) first = last = i;
    if (first > last) return std::nullopt;
  }
  const std::size_t margin = 6;
  if (first < margin || last + margin >= fraction.size()) return std::nullopt;
  first -= margin, last += margin;
  double area = 0.0;  // integral of (1 - f) over the window's rows
  for (std::size_t i = first; i < last; ++i) {
    const double gap = double(usedRows[i + 1] - usedRows[i]);
    area += gap * (2.0 - std::clamp(fraction[i], 0.0, 1.0) - std::clamp(fraction[i + 1], 0.0, 1.0)) / 2.0;
  }
  return double(usedRows[first]) + area;
}

// The first frame at the check's exposure. A camera that cannot lock (a recording) is measured at
// its own exposure: the references then still say whether the LED reaches its frames at all.
SeenFrame firstFrameAtExposure(CheckRig& rig, double exposureUs, double gain) {
  std::optional<SeenFrame> first;
  if (rig.lock({exposureUs, gain}).locked) {
    for (int n = 0; n < 20 && !first; ++n) {
      std::optional<SeenFrame> seen = rig.next(std::chrono::milliseconds(1000));
      if (!seen) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
      if (seen->frame.metadata.exposureLocks >= rig.locksMade()) first = std::move(seen);
    }
    if (!first)
      throw HardwareCheckError(rig.camera().id() + ": no frame taken under the exposure lock");
  } else {
    first = rig.next(std::chrono::milliseconds(1000));
    if (!first) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
  }
  return std::move(*first);
}

// The LED-on and LED-off rows, averaged over settled frames; leaves the LED off, `last` at the
// last off frame and counts the responding rows in `timing`.
Reference measureReferences(CheckRig& rig, const WhiteRows& whites, const capture::CodeTable& codes,
                            double framePeriodUs, int referenceFrames, SeenFrame& last,
                            LedTiming& timing) {
  Reference ref;
  rig.setLed(true);
  ref.on = averageRows(settledFrames(rig, referenceFrames, framePeriodUs), whites, codes);
  rig.setLed(false);
  const std::vector<SeenFrame> offFrames = settledFrames(rig, referenceFrames, framePeriodUs);
  ref.off = averageRows(offFrames, whites, codes);
  last = offFrames.back();
  ref.usable.assign(ref.on.size(), false);
  for (std::size_t r = 0; r < ref.on.size(); ++r)
    if (whites.usable(int(r)) && ref.on[r] - ref.off[r] > 0.05 * ref.on[r]) {
      ref.usable[r] = true;
      ++timing.respondingRows;
    }
  return ref;
}

// A scrambled order, so that a drift over the run does not look like a slope.
std::vector<int> scrambledOrder(int count) {
  std::vector<int> order;
  int stride = std::max(1, count / 3);
  while (std::gcd(stride, count) != 1) ++stride;
  for (int j = 0; j < count; ++j) order.push_back((j * stride) % count);
  return order;
}

// Passes of LED switches, once in every other frame, each at its phase after the middle of row
// 0's exposure, and the transitions they show in the frames.
class SwitchPasses {
 public:
  SwitchPasses(CheckRig& rig, const WhiteRows& whites, const capture::CodeTable& codes,
               double framePeriodUs, double lockedUs, const Reference& ref, SeenFrame last,
               LedTiming& timing)
      : rig_(rig), whites_(whites), codes_(codes), framePeriodUs_(framePeriodUs),
        lockedUs_(lockedUs), ref_(ref), last_(std::move(last)), timing_(timing) {}

  void run(const std::vector<double>& phasesUs) {
    std::vector<Planned> planned;
    std::uint64_t nextAllowed = last_.frame.metadata.sequence + 1;
    for (const double phaseUs : phasesUs) {
      const std::uint64_t k = std::max(nextAllowed, last_.frame.metadata.sequence + 1);
      planned.push_back(switchAt(k, phaseUs));
      nextAllowed = planned.back().frame + 2;
    }
    while (last_.frame.metadata.sequence < planned.back().frame + 3) {
      std::optional<SeenFrame> seen = rig_.next(std::chrono::milliseconds(1000));
      if (!seen) throw HardwareCheckError(rig_.camera().id() + ": no frame for a second");
      keep(std::move(*seen));
    }
    for (const Planned& p : planned) recordTransition(p);
  }

 private:
  struct Planned {
    std::int64_t atUs;
    std::uint64_t frame;
    bool toOn;
  };

  void keep(SeenFrame&& seen) {
    last_ = seen;
    frames_.emplace(seen.frame.metadata.sequence, std::move(seen));
  }

  double row0StartUs(std::uint64_t sequence) const {
    return double(*last_.frame.metadata.exposureStartUs) +
           (double(sequence) - double(last_.frame.metadata.sequence)) * framePeriodUs_;
  }

  // Switches at `phaseUs` in the first frame from `k` whose moment is still 2 ms ahead.
  Planned switchAt(std::uint64_t k, double phaseUs) {
    while (row0StartUs(k) + lockedUs_ / 2 + phaseUs < double(rig_.clock().nowUs()) + 2000.0) ++k;
    const std::int64_t atUs = std::int64_t(std::llround(row0StartUs(k) + lockedUs_ / 2 + phaseUs));
    // Take the frames that arrive meanwhile, then wait for the moment itself.
    while (rig_.clock().nowUs() < atUs) {
      const auto waitMs = std::chrono::milliseconds((atUs - rig_.clock().nowUs()) / 1000);
      if (waitMs.count() <= 0) break;
      if (std::optional<SeenFrame> seen = rig_.next(waitMs)) keep(std::move(*seen));
    }
    rig_.clock().sleepUntilUs(atUs);
    const std::int64_t switchedUs = rig_.setLed(!rig_.ledOn());
    ++timing_.switchesMade;
    return {switchedUs, k, rig_.ledOn()};
  }

  // The frames whose rows could hold the switch (by its recorded time: a busy loop switches
  // late), from the one whose row 0 starts a period after it to two before; a switch shows in
  // the frame aimed at unless the timestamps are off by a frame or more.
  void recordTransition(const Planned& p) {
    const double lastRow0StartUs = row0StartUs(last_.frame.metadata.sequence);
    const auto aimed =
        std::int64_t(std::floor((double(p.atUs) - lockedUs_ / 2 - lastRow0StartUs) / framePeriodUs_ +
                                double(last_.frame.metadata.sequence)));
    for (int shift = -1; shift <= 2; ++shift) {
      const auto found = frames_.find(std::uint64_t(aimed + shift));
      if (found == frames_.end() || !found->second.frame.metadata.exposureStartUs) continue;
      const hal::FrameMetadata& m = found->second.frame.metadata;
      const auto row =
          halfRow(whites_.rowMeans(found->second.frame, codes_), ref_, p.toOn, whites_);
      if (!row) continue;
      timing_.transitions.push_back(
          {double(p.atUs), *row, double(p.atUs) - double(*m.exposureStartUs) - m.exposureUs / 2.0,
           shift});
      break;
    }
  }

  CheckRig& rig_;
  const WhiteRows& whites_;
  const capture::CodeTable& codes_;
  const double framePeriodUs_, lockedUs_;
  const Reference& ref_;
  SeenFrame last_;
  std::map<std::uint64_t, SeenFrame> frames_;
  LedTiming& timing_;
};

// Second pass's phases: every switch aimed, from the first fit, at a row spread over the whites,
// which widens the lever arm of the line time and so pins the offset at row 0. Empty when the
// whites are too narrow for the ramp.
std::vector<double> aimedPhasesUs(const LedTiming& timing, const WhiteRows& whites, double lockedUs,
                                  int aimedSwitches) {
  const double rampRows = lockedUs / *timing.lineTimeUs;
  const double lo = whites.firstRow + rampRows / 2 + 8, hi = whites.lastRow - rampRows / 2 - 8;
  std::vector<double> phases;
  if (!(hi > lo)) return phases;
  for (int slot : scrambledOrder(aimedSwitches)) {
    const double row = lo + (hi - lo) * (slot + 0.5) / aimedSwitches;
    phases.push_back(*timing.lineTimeUs * row - *timing.offsetUs);
  }
  return phases;
}

}  // namespace

LedTiming measureLedTiming(CheckRig& rig, const WhiteRows& whites, const capture::CodeTable& codes,
                           double framePeriodUs, double brightExposureUs,
                           const LedTimingParams& params) {
  LedTiming timing;
  const double exposureUs = params.exposureUs;
  const double gain = std::clamp(brightExposureUs / exposureUs, 1.0, 16.0);
  SeenFrame last = firstFrameAtExposure(rig, exposureUs, gain);
  const double lockedUs = last.frame.metadata.exposureUs;
  const Reference ref =
      measureReferences(rig, whites, codes, framePeriodUs, params.referenceFrames, last, timing);
  if (timing.respondingRows < 16) {
    timing.problem = "the white references did not change when the LED switched (" +
                     std::to_string(timing.respondingRows) + " rows changed by more than 5 %)";
    return timing;
  }
  if (!last.frame.metadata.exposureStartUs) {
    timing.problem = rig.camera().id() +
                     " does not say when its frames were exposed (no exposure start or no "
                     "exposure time in the metadata)";
    return timing;
  }
  SwitchPasses passes(rig, whites, codes, framePeriodUs, lockedUs, ref, std::move(last), timing);
  // First pass: phases over the whole period; only those landing in the white rows are seen.
  std::vector<double> phases;
  for (int slot : scrambledOrder(params.switches))
    phases.push_back((slot + 0.5) / params.switches * framePeriodUs);
  passes.run(phases);
  fitLedTiming(timing, whites.heightPx);
  if (timing.lineTimeUs && *timing.lineTimeUs > 0 && params.aimedSwitches > 0) {
    phases = aimedPhasesUs(timing, whites, lockedUs, params.aimedSwitches);
    if (!phases.empty()) {
      passes.run(phases);
      timing.problem.clear();
    }
  }
  fitLedTiming(timing, whites.heightPx);
  return timing;
}

void fitLedTiming(LedTiming& timing, int heightPx) {
  const std::vector<LedTransition>& t = timing.transitions;
  if (t.size() < 3) {
    if (timing.problem.empty())
      timing.problem = "only " + std::to_string(t.size()) + " of " +
                       std::to_string(timing.switchesMade) +
                       " switches showed inside the white references (3 needed)";
    return;
  }
  double mx = 0, my = 0;
  for (const LedTransition& x : t) mx += x.halfRow / double(t.size()), my += x.sinceRow0Us / double(t.size());
  double sxx = 0, sxy = 0, lo = t[0].halfRow, hi = t[0].halfRow;
  for (const LedTransition& x : t) {
    sxx += (x.halfRow - mx) * (x.halfRow - mx);
    sxy += (x.halfRow - mx) * (x.sinceRow0Us - my);
    lo = std::min(lo, x.halfRow), hi = std::max(hi, x.halfRow);
  }
  if (hi - lo < 20.0) {
    timing.problem = "the switches seen span only " + std::to_string(int(hi - lo)) +
                     " rows (20 needed for a line time)";
    return;
  }
  const double line = sxy / sxx, intercept = my - line * mx;
  double ss = 0;
  for (const LedTransition& x : t) {
    const double r = x.sinceRow0Us - (intercept + line * x.halfRow);
    ss += r * r;
  }
  timing.lineTimeUs = line;
  timing.readoutUs = line * heightPx;
  // sinceRow0 = line x row - offset: the light changes `offset` after the record.
  timing.offsetUs = -intercept;
  timing.residualUs = std::sqrt(ss / double(t.size()));
  std::map<int, int> shifts;
  for (const LedTransition& x : t) ++shifts[x.frameShift];
  timing.frameShift = std::max_element(shifts.begin(), shifts.end(), [](const auto& a, const auto& b) {
                        return a.second < b.second;
                      })->first;
}

CheckItem ledTimingItem(const LedTiming& timing, const std::string& cameraId) {
  CheckItem item{"LED timing and readout", Verdict::Ok, "", ""};
  if (!timing.lineTimeUs) {
    item.verdict = Verdict::Fail;
    item.finding = cameraId + ": " + timing.problem;
    if (timing.respondingRows < 16 && timing.switchesMade == 0 && timing.problem.find("exposed") == std::string::npos)
      item.advice = "check that the LED lights the target (led_chip, led_line, led_active_low, the "
                    "driver's power); a file camera plays recorded frames and cannot see the LED. "
                    "Until measured, leave readout_us empty (a whole frame period: safe, more "
                    "frames rejected) and set led_frames_per_state = 4";
    else
      item.advice = "leave readout_us empty (a whole frame period: safe, more frames rejected) and "
                    "set led_frames_per_state = 4; keep the target still and in view, the room "
                    "light steady, and run the check again";
    return item;
  }
  char text[400];
  std::snprintf(text, sizeof text,
                "line time %.2f us (readout %.0f us), the light changes %.0f us after the "
                "recorded switch (fit residual %.0f us RMS, %zu of %d switches seen, in the frame "
                "aimed at %+d)",
                *timing.lineTimeUs, *timing.readoutUs, *timing.offsetUs, *timing.residualUs,
                timing.transitions.size(), timing.switchesMade, *timing.frameShift);
  item.finding = text;
  if (*timing.lineTimeUs <= 0.0) {
    item.verdict = Verdict::Fail;
    item.advice = "the rows do not follow the switches' times: the camera's timestamps may not "
                  "be its frames' own; check that nothing else drives the LED";
  } else if (std::abs(*timing.offsetUs) + 3.0 * *timing.residualUs > 10000.0) {
    item.verdict = Verdict::Fail;
    item.advice = "the camera's timestamps are off by more than led_guard_us can cover (10 ms): "
                  "the frames' exposure times are not what their metadata says; report the "
                  "camera and use led_frames_per_state = 4";
  } else if (*timing.frameShift != 0 || *timing.residualUs > 500.0) {
    item.verdict = Verdict::Warn;
    item.advice = "the LED's change shows in another frame than timed, or irregularly: widen "
                  "led_guard_us as printed below";
  }
  return item;
}

}  // namespace slicecap::hwcheck
