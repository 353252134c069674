// A session's state as the replies show it (control::SessionView), made from its store.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "slicecap/capture/pass_again.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"

namespace slicecap::daemon {

/// \brief The whole session: what session.new/show/resume answer and an export's summary holds.
control::SessionView sessionView(const capture::SessionStore& store);
/// \brief The session as the status shows it: without its folder, creation time and the
/// journal's recovery figures.
control::SessionView statusSessionView(const capture::SessionStore& store);
/// \brief capture::binsToPassAgain of a session's slices, kept while a slice's bins stay the
/// same (AzimuthBins::version): it reads every cell of the slice (~10 ms for 300 frames of 64
/// cells on a desktop core), and the status is asked for on the frame loop, often during a sweep.
/// The cells are read as the slice's texture verdict says (capture::cellsAsJudged): a finished
/// slice judged once, the running sweep as its frames grow (capture::RunningCellTexture).
class PassAgainCache {
 public:
  const std::vector<capture::PassAgainBin>& bins(const capture::SessionStore& store,
                                                 const SliceId& slice,
                                                 capture::SweepProgress progress);
  /// \brief The texture verdict bins() read the slice's cells with (judged here if not yet).
  const capture::CellTexture& texture(const capture::SessionStore& store, const SliceId& slice,
                                      capture::SweepProgress progress);

 private:
  struct Kept {
    std::uint64_t version = 0;
    capture::CellTexture texture;
    std::vector<capture::PassAgainBin> bins;
  };
  Kept& kept(const capture::SessionStore& store, const SliceId& slice,
             capture::SweepProgress progress);
  std::map<std::pair<SliceId, capture::SweepProgress>, Kept> kept_;
  std::map<SliceId, capture::RunningCellTexture> running_;
};

/// \brief The texture verdicts of the session's finished sweeps whose frames carry window cells
/// (the running sweep's is still being judged), in sweep order: the status's "cell_texture".
std::vector<control::CellTextureView> cellTextureView(const capture::SessionStore& store,
                                                      const std::optional<SliceId>& sweeping,
                                                      PassAgainCache& cache);

/// \brief The bins of the session's swept slices to pass again (capture::binsToPassAgain), in
/// sweep order: `sweeping`'s slice as a sweep still under way (its empty bins ahead of it are not
/// named), every other slice with samples as finished.
std::vector<control::PassAgainView> passAgainView(const capture::SessionStore& store,
                                                  const std::optional<SliceId>& sweeping,
                                                  PassAgainCache& cache);
/// \brief What refuseSlice did, and its sentence for the status's error.
struct RefusalOutcome {
  bool recorded = false;  ///< in the journal: the run's samples are set aside
  std::string said;
};
/// \brief Refuses the sweep run of `slice` whose samples start at journal record `firstRecord`
/// in `store` (SessionStore::refuse, with the run's texture frames) and says so for the status's error; a refusal that cannot
/// be journaled is logged and said (the samples then count).
RefusalOutcome refuseSlice(capture::SessionStore& store, const SliceId& slice,
                           const std::string& reason, std::uint64_t firstRecord,
                           std::optional<capture::RunTextureFrames> textureFrames);
/// \brief One sentence for each refused sweep of the session (SessionStore::refusals), for the
/// export: the slice, the samples set aside and why.
std::vector<std::string> refusalWarnings(const capture::SessionStore& store);
/// \brief The command that starts (or continues) a slice's sweep, for the hints.
std::string startCommand(const SliceId& slice);
/// \brief The time now in UTC, formatted by strftime's `format`.
std::string utcNow(const char* format);

}  // namespace slicecap::daemon
