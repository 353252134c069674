// A session's state as the replies show it: its slices in sweep order and its journal's damage.
#include "session_report.hpp"

#include <chrono>
#include <ctime>
#include <iostream>

#include "slicecap/daemon/session_manager.hpp"

namespace slicecap::daemon {
namespace {

std::vector<control::SliceProgress> sliceProgress(const capture::SessionStore& store) {
  std::vector<control::SliceProgress> slices;
  for (const SliceId& slice : sweepOrder()) {
    std::optional<std::string> refused;  // the slice's latest refusal
    for (const capture::SweepRefusal& refusal : store.refusals())
      if (refusal.slice == slice) refused = refusal.reason;
    slices.push_back({slice, store.sampleCount(slice), store.bins(slice).filledCount(),
                      store.setAsideCount(slice), store.damaged(slice), std::move(refused)});
  }
  return slices;
}

// What replaying the journal could not tell for sure: each with the file and line in its message.
std::vector<control::JournalDamageView> journalDamage(const capture::SessionStore& store) {
  std::vector<control::JournalDamageView> damage;
  for (const capture::JournalDamage& d : store.damage()) {
    std::vector<std::string> slices;
    for (const SliceId& slice : d.slicesSetAside)
      slices.push_back(toString(slice));
    damage.push_back({d.line, d.message, std::move(slices), d.samplesSetAside, d.samplesLost});
  }
  return damage;
}

}  // namespace

control::SessionView statusSessionView(const capture::SessionStore& store) {
  control::SessionView session;
  session.id = store.info().id;
  session.material = store.info().material;
  session.samples = store.sampleCount();
  session.slices = sliceProgress(store);
  session.journalDamage = journalDamage(store);
  return session;
}

control::SessionView sessionView(const capture::SessionStore& store) {
  control::SessionView session = statusSessionView(store);
  session.createdUtc = store.info().createdUtc;
  session.directory = store.directory().string();
  if (store.recovery().tornTailBytes > 0)
    session.tornTailBytesDropped = store.recovery().tornTailBytes;
  session.corruptJournalLines.assign(store.recovery().corruptLines.begin(),
                                     store.recovery().corruptLines.end());
  return session;
}

const std::vector<capture::PassAgainBin>& PassAgainCache::bins(const capture::SessionStore& store,
                                                               const SliceId& slice,
                                                               capture::SweepProgress progress) {
  const capture::AzimuthBins& bins = store.bins(slice);
  Kept& kept = kept_[{slice, progress}];
  // A finished slice's bins change no more: its texture is judged once, and its cells read as
  // the verdict says. A sweep under way is read as it is (the verdict needs the whole sweep,
  // and judging it on every frame would cost the frame loop).
  if (kept.version != bins.version())
    kept = {bins.version(),
            capture::binsToPassAgain(bins, slice, progress, {},
                                     progress == capture::SweepProgress::Finished
                                         ? capture::cellTextureOf(bins)
                                         : capture::CellTexture{})};
  return kept.bins;
}

std::vector<control::PassAgainView> passAgainView(const capture::SessionStore& store,
                                                  const std::optional<SliceId>& sweeping,
                                                  PassAgainCache& cache) {
  std::vector<control::PassAgainView> out;
  for (const SliceId& slice : sweepOrder()) {
    const auto progress = slice == sweeping ? capture::SweepProgress::Running
                                            : capture::SweepProgress::Finished;
    for (const capture::PassAgainBin& bin : cache.bins(store, slice, progress))
      out.push_back({bin.slice, bin.azimuthDeg, toString(bin.reason)});
  }
  return out;
}

std::string refuseSlice(capture::SessionStore& store, const SliceId& slice, const std::string& reason) {
  const std::string what = "sweep " + toString(slice) + " refused";
  try {
    store.refuse(slice, reason);
    return what + ", its samples set aside (kept in the session, used by no table): " + reason;
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: " << what << ", but the refusal was not recorded: " << error.what()
              << "\n";
    return what + " (" + reason + "), but the refusal could not be recorded (" + error.what() +
           "): its samples still count";
  }
}

std::vector<std::string> refusalWarnings(const capture::SessionStore& store) {
  std::vector<std::string> out;
  for (const capture::SweepRefusal& refusal : store.refusals())
    out.push_back("sweep " + toString(refusal.slice) + " refused: its " +
                  std::to_string(refusal.samplesSetAside) +
                  " samples are set aside (kept in the session's journal, used by no table or "
                  "export): " + refusal.reason);
  return out;
}

std::string startCommand(const SliceId& slice) {
  return "slicecap sweep start " + std::string(toString(slice.kind)) + " " +
         std::to_string(slice.elevations.thetaIDeg) + " " +
         std::to_string(slice.elevations.thetaVDeg);
}

std::string utcNow(const char* format) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, format, &utc);
  return text;
}

}  // namespace slicecap::daemon
