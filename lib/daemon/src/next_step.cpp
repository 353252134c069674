// The status's next step: keep sweeping, the next slice in sweep order, or export.
#include "next_step.hpp"

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

}  // namespace

std::string nextStep(const capture::SessionStore* session, const SweepRun* sweep,
                     const std::optional<control::IsotropyView>& isotropy) {
  if (!session) return "slicecap session new MATERIAL";
  if (sweep) return sweepStep(*session, *sweep);
  const std::string exportCommand = "slicecap export " + session->info().id + " -o DIR";
  // A slice with samples counts as swept: a hand-held sweep seldom fills all 24 bins, and a
  // hint that waits for them never moves on. The sparsest slice is named at the end.
  for (const SliceId& slice : sweepOrder()) {
    if (session->sampleCount(slice) > 0) continue;
    if (slice.kind == SliceKind::Diagonal) return startCommand(slice);
    return axialStep(slice, exportCommand, isotropy);
  }
  return exportStep(*session, exportCommand);
}

}  // namespace slicecap::daemon
