// What a sweep's samples say about the decoding of a processed (8-bit) stream, for `slicecap
// status`: whether its tone curve stays the same from frame to frame, and whether its colour
// processing takes a channel below black.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/control/reply_views.hpp"

namespace slicecap::daemon {

/// \brief What becomes of a run the rule finds broken (DecodingWatch::unlitVerdict's words).
enum class RefusalPolicy {
  Refuse,     ///< refuse_broken_decoding, and a session takes the refusal as the run ends
  Refused,    ///< the run has ended refused: its samples and texture frames were set aside
  WarnOnly,   ///< refuse_broken_decoding = false: kept, warned of
  NoSession,  ///< refuse_broken_decoding, but no session was open as the run began: no samples
              ///< of it were recorded, so none are set aside
};

/// \brief The latest samples' black-patch readings (FrameOutcome::Measurement::blackReading) and
/// the window's pixels at code 0 (windowAtBlack), and the warnings they call for: a decoding no
/// measured curve can be trusted with. Measured on the camera model (docs/results/
/// 2026-12-06-real-sensors-goals.md, "The decoding checks").
class DecodingWatch {
 public:
  /// \brief The black patch's reading stepping by more than this, on average, from a sample to
  /// the sample of the next frame (relative, signed: the mean over the latest pairs), and that
  /// mean more than kMinStepSigmas of its standard errors from 0: the camera stretches its tone
  /// curve per frame (a Raspberry Pi's rpi.contrast ce_enable) from the frame before, so the
  /// first LED-on frame after an LED-off one (a dark frame's stretch) and the next (a lit
  /// frame's) read the black against the whites differently every time, which one measured curve
  /// cannot decode. Noise steps either way and averages out; the view moving steps both ways too.
  static constexpr double kMaxBlackReadingStep = 0.01;
  static constexpr double kMinStepSigmas = 4.0;
  /// \brief A window channel's light over the white references' (the sample's value, before its
  /// clip at 0) stepping by more than this, on average, from a sample to the next frame's, and
  /// more than kMinStepSigmas of its standard errors from 0: the same per-frame stretch, seen where
  /// it does the harm. rpi.contrast keeps the histogram's median as a fixed point and stretches
  /// above it, so a channel between the 1 % point and the median is read through an LED-off
  /// frame's stretch in the block's first LED-on frame and through the identity in the next: a
  /// dark channel moves against the whites by about a percent, one way every block (the camera
  /// model: 1.3 % in red with the stretch, under 0.1 % without, on the still rig). The black
  /// patch sits below the 1 % point, where every stretch is the identity, which is why its step
  /// does not see it.
  static constexpr double kMaxWindowStep = 0.005;
  /// \brief More than this fraction of a window channel's pixels at code 0 (median over the
  /// latest samples): light below black. Noise where the light is at black leaves about half at
  /// 0 (a little more: code 0 also holds the light below half-way to code 1); a colour matrix
  /// that mixes the channels takes a saturated colour's weak channel negative and the ISP clips
  /// it. On an RGB stream nearly all its pixels are then at 0; a YUV420 stream's shared chroma
  /// spreads them over codes 0..3, and the camera model's processed-isp sweeps read 46-73 %.
  static constexpr double kMaxWindowAtBlack = 0.6;
  /// \brief A window channel's LED light (FrameOutcome::Measurement::windowLight, the sample's
  /// value before its clip at 0) whose median over the latest samples lies more than this many
  /// of its standard errors below 0 is light the decoding took below black, and the sweep is
  /// refused. The LED only adds light: an honest channel, however dark (a black material), reads
  /// noise around a mean at or above 0, while a colour matrix that mixes the channels (a
  /// Raspberry Pi's rpi.ccm) clips a saturated colour's weak channel at black, or a tone curve
  /// the fit misses puts it below the black reference, and the LED-on frames read it below
  /// the LED-off frames, tightly, in nearly every sample (the camera model's processed-isp
  /// frames: G 35-110 standard errors below 0). The median, not the mean, and the standard
  /// error from the median absolute deviation (1.2533 x 1.4826 x MAD / sqrt(n)): a highlight's
  /// samples, where the matrix leaves the channel above 0, move neither. Honest channels with
  /// Gaussian noise around +0.2 sigma are refused in 1 % of runs of 4 samples, 0.55 % of 8 and
  /// none of 2000 of 32, with kMinMeanBelowBlackSigmas (docs/real-sensors.md, "Refused sweeps");
  /// the rule before this one (more than half at or below 0) refused 13-21 %.
  static constexpr double kMinBelowBlackSigmas = 6.0;
  /// \brief From kMinSamples samples on, a channel is also refused when the mean of its samples
  /// within kTrimSigmas robust standard deviations of their median (a highlight's samples, above
  /// 0, left out) lies more than this many of its standard errors below 0: where a broken
  /// channel's noise is as wide as its distance below 0 (the camera model's processed-isp
  /// diagonal 75/75: median 2.3 standard errors below 0, this mean 5.4), the mean of the many
  /// samples sees what the median's wider error hides. Honest channels, both rules together:
  /// docs/real-sensors.md, "Refused sweeps" (under 1 % of runs of 8 samples at +0.2 sigma,
  /// none of 32).
  static constexpr double kMinMeanBelowBlackSigmas = 3.0;
  static constexpr double kTrimSigmas = 5.0;
  /// \brief More than this fraction of the latest samples with a channel's LED light exactly 0
  /// is a channel the clip pinned (LED-on and LED-off frames read alike at black): refused too.
  /// Noise never lands an honest channel's light exactly on 0.
  static constexpr double kMaxWindowPinned = 0.5;
  /// \brief The refusal needs this many samples in the run: a run whose frames were mostly
  /// dropped (a loaded machine: 5 samples a sweep) is still judged; fewer samples are not.
  static constexpr std::size_t kMinRefusalSamples = 4;
  /// \brief window_unlit_sigmas is held within +-this (a spread of 0 gives no ratio).
  static constexpr double kSigmasCap = 1000.0;
  /// \brief The figures of this many latest samples count.
  static constexpr std::size_t kSamples = 32;
  /// \brief A figure needs this many samples before it warns.
  static constexpr std::size_t kMinSamples = 8;

  /// \brief A new sweep run: nothing seen yet.
  void reset();
  /// \brief A settled outcome of the frame numbered `sequence` (FrameMetadata::sequence): a
  /// sample's black reading and window channels at code 0.
  void note(const capture::FrameOutcome& outcome, std::uint64_t sequence);
  /// \brief The status's "decoding_check" figures (none before the first sample).
  control::DecodingCheckView view() const;
  /// \brief A sentence for each figure beyond its limit, naming it, the limit and what to do;
  /// only for 8-bit frames (a RAW stream's figures are noise).
  std::vector<std::string> warnings() const;
  /// \brief Why the sweep run's samples must not be used: its decoding is shown broken (over at
  /// least kMinRefusalSamples, a window channel's LED light below 0 by more than
  /// kMinBelowBlackSigmas, or exactly 0 in more than kMaxWindowPinned of the samples), with the
  /// figures, the limits and what to do; nullopt otherwise and for a linear 16-bit stream.
  std::optional<std::string> refusal() const;
  /// \brief What the rule makes of the run so far, for the status's window_unlit_verdict: not
  /// judged (a linear stream, too few samples), kept, or, broken, what `policy` does with it:
  /// refused as the run ends (or, once it has ended, refused), only warned of, or not refused
  /// for want of a session. Nullopt before a sample.
  std::optional<std::string> unlitVerdict(RefusalPolicy policy) const;

 private:
  std::deque<double> readings_, steps_;
  std::optional<std::uint64_t> lastSequence_;  ///< the frame of readings_.back()
  std::array<std::deque<double>, 3> atBlack_;
  std::array<std::deque<double>, 3> lights_;  ///< the samples' windowLight, the longest level's
  std::array<std::deque<double>, 3> windowSteps_;
  std::optional<Rgb> lastWindowLight_;  ///< the window light of the frame lastWindowSequence_
  std::optional<std::uint64_t> lastWindowSequence_;
  bool eightBit_ = false;
};

}  // namespace slicecap::daemon
