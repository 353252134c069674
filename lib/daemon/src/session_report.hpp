// A session's state as the replies show it (control::SessionView), made from its store.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"

namespace slicecap::daemon {

/// \brief The whole session: what session.new/show/resume answer and an export's summary holds.
control::SessionView sessionView(const capture::SessionStore& store);
/// \brief The session as the status shows it: without its folder, creation time and the
/// journal's recovery figures.
control::SessionView statusSessionView(const capture::SessionStore& store);
/// \brief The bins of the session's swept slices to pass again (capture::binsToPassAgain), in
/// sweep order: `sweeping`'s slice as a sweep still under way (its empty bins ahead of it are not
/// named), every other slice with samples as finished.
std::vector<control::PassAgainView> passAgainView(const capture::SessionStore& store,
                                                  const std::optional<SliceId>& sweeping);
/// \brief The command that starts (or continues) a slice's sweep, for the hints.
std::string startCommand(const SliceId& slice);
/// \brief The time now in UTC, formatted by strftime's `format`.
std::string utcNow(const char* format);

}  // namespace slicecap::daemon
