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
                      store.setAsideCount(slice), store.refusedCount(slice), store.damaged(slice),
                      std::move(refused)});
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

// Whether any frame of the slice carries window cells: a session captured without them has no
// texture to judge, and its slices no verdict to show.
bool hasWindowCells(const capture::AzimuthBins& bins) {
  for (int b = 0; b < bins.binCount(); ++b)
    for (const capture::FrameSample& frame : bins.samplesIn(b))
      if (frame.cells) return true;
  return false;
}

}  // namespace

const std::vector<SliceId>& sweepOrder() {
  static const std::vector<SliceId> order{
      {SliceKind::Diagonal, {30, 30}}, {SliceKind::Diagonal, {75, 75}},
      {SliceKind::Diagonal, {30, 75}}, {SliceKind::Diagonal, {75, 30}},
      {SliceKind::Axial, {30, 30}},    {SliceKind::Axial, {30, 75}},
      {SliceKind::Axial, {75, 30}},    {SliceKind::Axial, {75, 75}}};
  return order;
}

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

PassAgainCache::Kept& PassAgainCache::kept(const capture::SessionStore& store,
                                           const SliceId& slice,
                                           capture::SweepProgress progress) {
  const capture::AzimuthBins& bins = store.bins(slice);
  Kept& kept = kept_[{slice, progress}];
  if (kept.version == bins.version()) return kept;
  // A finished slice's bins change no more: its texture is judged once. A sweep under way is
  // judged again as its frames grow, so a textured window's thread is not named a missed peak
  // while it runs (judging it on every frame would cost the frame loop).
  if (progress == capture::SweepProgress::Finished) {
    running_.erase(slice);
    kept.texture = capture::cellTextureOf(bins);
  } else {
    kept.texture = running_[slice].of(bins);
  }
  kept.bins = capture::binsToPassAgain(bins, slice, progress, {}, kept.texture);
  kept.version = bins.version();
  return kept;
}

const std::vector<capture::PassAgainBin>& PassAgainCache::bins(const capture::SessionStore& store,
                                                               const SliceId& slice,
                                                               capture::SweepProgress progress) {
  return kept(store, slice, progress).bins;
}

const capture::CellTexture& PassAgainCache::texture(const capture::SessionStore& store,
                                                    const SliceId& slice,
                                                    capture::SweepProgress progress) {
  return kept(store, slice, progress).texture;
}

std::vector<control::CellTextureView> cellTextureView(const capture::SessionStore& store,
                                                      const std::optional<SliceId>& sweeping,
                                                      PassAgainCache& cache) {
  std::vector<control::CellTextureView> out;
  for (const SliceId& slice : sweepOrder()) {
    if (slice == sweeping || !hasWindowCells(store.bins(slice))) continue;
    const capture::CellTexture& texture =
        cache.texture(store, slice, capture::SweepProgress::Finished);
    std::optional<double> spread;
    if (!texture.albedoFactors.empty()) spread = texture.spreadPercent;
    out.push_back({slice, std::string(toString(texture.action)), spread,
                   capture::verdictReason(texture)});
  }
  return out;
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

RefusalOutcome refuseSlice(capture::SessionStore& store, const SliceId& slice,
                           const std::string& reason, std::uint64_t firstRecord,
                           std::optional<capture::RunTextureFrames> textureFrames) {
  const std::string what = "sweep " + toString(slice) + " refused";
  try {
    store.refuse(slice, reason, firstRecord, textureFrames);
    const std::size_t count = store.refusals().back().samplesSetAside;
    return {true, what + ", the run's " + std::to_string(count) +
                      " samples set aside (kept in the session, used by no table): " + reason};
  } catch (const std::exception& error) {
    std::cerr << "slicecapd: " << what << ", but the refusal was not recorded: " << error.what()
              << "\n";
    return {false, what + " (" + reason + "), but the refusal could not be recorded (" +
                       error.what() + "): its samples still count"};
  }
}

std::vector<std::string> refusalWarnings(const capture::SessionStore& store) {
  std::vector<std::string> out;
  for (const capture::SweepRefusal& refusal : store.refusals())
    out.push_back("sweep " + toString(refusal.slice) + " refused: the run's " +
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
