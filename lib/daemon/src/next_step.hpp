// The status's "next": what the person at the rig does now, as a command where there is one.
#pragma once

#include <optional>
#include <string>

#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"
#include "session_report.hpp"
#include "sweep_run.hpp"

namespace slicecap::daemon {

/// \brief The next step for the current session (none: start one), its sweep if any, and the
/// isotropy test's verdict on it if there is one. When bins are to be passed again
/// (capture::binsToPassAgain) the step ends by naming them: the sweep's own while it runs, else
/// one slice's (the first in sweep order with a peak not reached, else with a gap the hand left)
/// and the command that continues it.
/// `cache` keeps the bins to pass again between calls.
std::string nextStep(const capture::SessionStore* session, const SweepRun* sweep,
                     const std::optional<control::IsotropyView>& isotropy,
                     PassAgainCache& cache);

}  // namespace slicecap::daemon
