// The status's next step: keep sweeping, the next slice in sweep order, or export.
#include "next_step.hpp"

#include <cmath>

#include "session_report.hpp"
#include "slicecap/daemon/session_manager.hpp"

namespace slicecap::daemon {
namespace {

using control::kBinsPerSlice;

std::string binsOf(int filled) {
  return std::to_string(filled) + " of " + std::to_string(kBinsPerSlice) + " bins";
}

std::string sweepStep(const capture::SessionStore& session, const SweepRun& sweep) {
  if (sweep.paused) return sweep.pauseReason;
  const int filled = session.bins(sweep.slice).filledCount();
  if (filled >= kBinsPerSlice)
    return "all " + std::to_string(kBinsPerSlice) + " bins filled: slicecap sweep stop";
  return "keep sweeping " + toString(sweep.slice) + ": " + binsOf(filled) + " filled";
}

// Every slice swept: export, naming the sparsest slice when it could take more.
std::string exportStep(const capture::SessionStore& session, const std::string& exportCommand) {
  std::optional<SliceId> sparsest;
  auto filled = [&](const SliceId& slice) { return session.bins(slice).filledCount(); };
  for (const SliceId& slice : sweepOrder())
    if (!sparsest || filled(slice) < filled(*sparsest)) sparsest = slice;
  std::string hint = "every slice is swept: " + exportCommand;
  if (filled(*sparsest) < kBinsPerSlice)
    hint += " (the sparsest, " + toString(*sparsest) + ", has " + binsOf(filled(*sparsest)) +
            ": `" + startCommand(*sparsest) + "` adds to it)";
  return hint;
}

// The diagonal slices are swept, the axial one `axial` is next: does the isotropy test spare it?
std::string axialStep(const SliceId& axial, const std::string& exportCommand,
                      const std::optional<control::IsotropyView>& isotropy) {
  if (isotropy && !isotropy->axialSweepsNeeded)
    return "the diagonal sweeps look isotropic, the axial sweeps are not needed: " +
           exportCommand + " (to measure them anyway: " + startCommand(axial) + ")";
  if (isotropy && !isotropy->error && isotropy->isotropic == false)
    return "the diagonal sweeps show anisotropy: " + startCommand(axial);
  if (isotropy && !isotropy->error && !isotropy->informative)
    return "cannot tell yet whether the axial sweeps are needed (" + isotropy->reason + "): " +
           startCommand(axial) + " measures them";
  return startCommand(axial);
}

// "90 deg (peak not reached), 165-345 deg (empty)": the bins of `slice` to pass again, a run
// of neighbouring bins with one reason as a range (a half-swept slice has a dozen empty bins).
std::string azimuthsOf(const SliceId& slice, const std::vector<control::PassAgainView>& bins) {
  constexpr double kBinWidthDeg = 360.0 / kBinsPerSlice;
  std::vector<const control::PassAgainView*> of;
  for (const control::PassAgainView& bin : bins)
    if (bin.slice == slice) of.push_back(&bin);
  std::string out;
  for (std::size_t k = 0; k < of.size();) {
    std::size_t last = k;
    while (last + 1 < of.size() && of[last + 1]->reason == of[k]->reason &&
           std::abs(of[last + 1]->azimuthDeg - of[last]->azimuthDeg - kBinWidthDeg) < 1e-6)
      ++last;
    out += (out.empty() ? "" : ", ") + std::to_string(std::lround(of[k]->azimuthDeg));
    if (last > k) out += "-" + std::to_string(std::lround(of[last]->azimuthDeg));
    out += std::string(" deg (") + (of[k]->reason == "empty" ? "empty" : "peak not reached") + ")";
    k = last + 1;
  }
  return out;
}

// The hint's tail naming the bins to pass again: the sweep's own while one runs; else the first
// slice in sweep order with a peak not reached, else with a gap. After a sweep only what the hand
// skipped is named (capture::SweepProgress::Running: the longest stretch of empty bins is the
// part not swept, which the sparsest slice's hint speaks of), or a half sweep would list a dozen
// bins after every slice; the status's pass_again lists them all.
std::string passAgainHint(const capture::SessionStore& session, const SweepRun* sweep,
                          PassAgainCache& cache) {
  auto skipped = [&](const SliceId& slice) {
    std::vector<control::PassAgainView> out;
    for (const capture::PassAgainBin& bin :
         cache.bins(session, slice, capture::SweepProgress::Running))
      out.push_back({bin.slice, bin.azimuthDeg, toString(bin.reason)});
    return out;
  };
  if (sweep) {
    const std::string azimuths = azimuthsOf(sweep->slice, skipped(sweep->slice));
    return azimuths.empty() ? "" : "; pass again slowly over " + azimuths;
  }
  std::optional<SliceId> withGap;
  for (const SliceId& slice : sweepOrder()) {
    const std::vector<control::PassAgainView> bins = skipped(slice);
    for (const control::PassAgainView& bin : bins)
      if (bin.reason != "empty")
        return "; to pass again slowly: `" + startCommand(slice) + "` over " +
               azimuthsOf(slice, bins);
    if (!withGap && !bins.empty()) withGap = slice;
  }
  if (!withGap) return "";
  return "; to pass again slowly: `" + startCommand(*withGap) + "` over " +
         azimuthsOf(*withGap, skipped(*withGap));
}

std::string stepWithoutPassAgain(const capture::SessionStore& session,
                                 const std::optional<control::IsotropyView>& isotropy) {
  const std::string exportCommand = "slicecap export " + session.info().id + " -o DIR";
  // A slice with samples counts as swept: a hand-held sweep seldom fills all 24 bins, and a
  // hint that waits for them never moves on. The sparsest slice is named at the end.
  for (const SliceId& slice : sweepOrder()) {
    if (session.sampleCount(slice) > 0) continue;
    if (slice.kind == SliceKind::Diagonal) return startCommand(slice);
    return axialStep(slice, exportCommand, isotropy);
  }
  return exportStep(session, exportCommand);
}

}  // namespace

std::string nextStep(const capture::SessionStore* session, const SweepRun* sweep,
                     const std::optional<control::IsotropyView>& isotropy,
                     PassAgainCache& cache) {
  if (!session) return "slicecap session new MATERIAL";
  const std::string step =
      sweep ? sweepStep(*session, *sweep) : stepWithoutPassAgain(*session, isotropy);
  return step + passAgainHint(*session, sweep, cache);
}

}  // namespace slicecap::daemon
