// The isotropy test's answer on the current session, kept until its samples change.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/daemon/session_manager.hpp"

namespace slicecap::daemon {

/// \brief Runs the injected isotropy test once each of the four diagonal slices has samples, and
/// keeps the answer for a state of the samples (`samplesVersion`).
class IsotropyCache {
 public:
  explicit IsotropyCache(IsotropyFunction isotropy) : isotropy_(std::move(isotropy)) {}

  /// \brief Whether the axial sweeps are needed; nullopt without a test or before each diagonal
  /// slice has samples. While `capturing`, an earlier answer for the session stands. A test that
  /// throws gives an answer with its error.
  std::optional<control::IsotropyView> verdict(const capture::SessionStore& session,
                                               std::uint64_t samplesVersion, bool capturing) const;

 private:
  control::IsotropyView run(const capture::SessionStore& session) const;

  struct Answer {
    std::string session;
    std::uint64_t samplesVersion = 0;
    control::IsotropyView view;
  };
  IsotropyFunction isotropy_;
  mutable std::optional<Answer> answer_;
};

}  // namespace slicecap::daemon
