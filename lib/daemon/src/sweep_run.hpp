// The sweep of one slice while it runs or is paused: what the frame loop has told of it.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>

#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"

namespace slicecap::daemon {

/// \brief One slice's sweep: started, possibly paused with a reason, counting the accepted
/// frames of its current run (from its start or continuation to its pause: what a refusal
/// judges) and its rejected frames. The samples themselves are in the session's store.
struct SweepRun {
  explicit SweepRun(const SliceId& swept) : slice(swept) {}

  /// \brief Pauses with `reason` as the status and the next step show it.
  void pause(std::string reason) {
    paused = true;
    pauseReason = std::move(reason);
  }
  /// \brief Continues after a pause: a new run, whose accepted frames count from 0 (the paused
  /// view still showed the run that ended).
  void resume() {
    paused = false;
    pauseReason.clear();
    acceptedThisRun = 0;
  }
  bool capturing() const { return !paused; }
  /// \brief "running" or "paused", for refusals.
  const char* stateWord() const { return paused ? "paused" : "running"; }

  /// \brief The sweep as its replies and the status show it; `store` holds its bins and samples.
  control::SweepView view(const capture::SessionStore& store) const {
    control::SweepView view;
    view.slice = slice;
    view.state = paused ? "paused" : "capturing";
    view.bins = store.bins(slice).filled();
    view.binsFilled = store.bins(slice).filledCount();
    view.clippedBins = store.bins(slice).clippedBins();
    view.samples = store.sampleCount(slice);
    view.acceptedThisRun = acceptedThisRun;
    view.rejected = rejected;
    view.viewElevationErrorDeg = viewElevationErrorDeg;
    if (paused) view.pauseReason = pauseReason;
    return view;
  }

  SliceId slice;
  bool paused = false;
  std::string pauseReason;
  std::size_t acceptedThisRun = 0;
  std::map<std::string, std::size_t> rejected;
  std::optional<double> viewElevationErrorDeg;
};

}  // namespace slicecap::daemon
