// Sessions and sweeps behind the control protocol: every change durable before its reply.
#include "slicecap/daemon/session_manager.hpp"

#include <fstream>
#include <iostream>
#include <stdexcept>
#include <system_error>

#include "isotropy_cache.hpp"
#include "next_step.hpp"
#include "session_report.hpp"
#include "slicecap/capture/capture_error.hpp"
#include "slicecap/core/session_id.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/io/file_set.hpp"
#include "slicecap/io/io_error.hpp"
#include "storage_lock.hpp"
#include "sweep_run.hpp"

namespace slicecap::daemon {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

RequestError conflict(const std::string& message) {
  return RequestError(control::ErrorCode::Conflict, message);
}

RequestError noSuchSession(const std::string& id) {
  return RequestError(control::ErrorCode::NotFound, "no session '" + id + "'");
}

}  // namespace

struct SessionManager::State {
  State(fs::path storageRoot, SessionExporter sessionExporter, IsotropyFunction isotropyTest)
      : root(std::move(storageRoot)),
        lock(root),
        exporter(std::move(sessionExporter)),
        isotropy(std::move(isotropyTest)) {}

  fs::path root;
  StorageLock lock;
  SessionExporter exporter;
  IsotropyCache isotropy;
  std::optional<capture::SessionStore> session;
  std::optional<SweepRun> sweep;
  std::string lastError;
  std::uint64_t samplesVersion = 0;  // bumped whenever a session's samples may have changed
  mutable PassAgainCache passAgain;  // the status is const, its cells' reading kept

  fs::path currentFile() const { return root / "current"; }

  bool capturing() const { return sweep && sweep->capturing(); }

  void makeCurrent(capture::SessionStore store) {
    ++samplesVersion;
    session.emplace(std::move(store));
    io::writeFileAtomically(currentFile(), session->info().id + "\n");
    sweep.reset();
    lastError.clear();  // it told of the sweep that went with the session before
    if (const std::optional<SliceId> active = session->activeSweep()) {
      sweep.emplace(*active);
      sweep->pause("interrupted (the daemon stopped during this sweep); `" +
                   startCommand(*active) + "` continues it");
    }
  }

  capture::SessionStore& current() {
    if (!session)
      throw conflict(
          "no current session: `slicecap session new MATERIAL` or `slicecap session resume ID`");
    return *session;
  }

  bool exists(const std::string& id) const { return fs::is_directory(root / id); }

  void requireNoSweep(const char* what) const {
    if (sweep)
      throw conflict(std::string("cannot ") + what + " while sweep " + toString(sweep->slice) +
                     " is " + sweep->stateWord() + ": `slicecap sweep stop` first");
  }

  /// The session a command names, or the current one; a temporary store for another session.
  capture::SessionStore& target(const std::optional<std::string>& id,
                                std::optional<capture::SessionStore>& other) {
    if (!id || (session && session->info().id == *id)) return current();
    if (!exists(*id)) throw noSuchSession(*id);
    other.emplace(capture::SessionStore::open(root, *id));
    return *other;
  }

  std::string newSessionId() const {
    const std::string base = utcNow("s%Y%m%d-%H%M%S");
    std::string id = base;
    for (int suffix = 2; exists(id); ++suffix)
      id = base + "-" + std::to_string(suffix);
    return id;
  }

  json sessionReply() const { return control::toJson(sessionView(*session)); }
  json sweepReply() const { return control::toJson(sweep->view(*session)); }

  json run(const control::Hello&) {
    return {{"daemon", "slicecapd"}, {"version", kVersion}, {"protocol", control::kProtocolVersion}};
  }

  json run(const control::SessionNew& command) {
    requireNoSweep("start a new session");
    const std::string id = command.id.value_or(newSessionId());
    // <root>/current names the current session: a session folder of that name could never be
    // made current (nor could any other after it, the file's place being taken).
    if (id == currentFile().filename())
      throw RequestError(control::ErrorCode::BadRequest,
                         "session id '" + id +
                             "' is reserved (the storage folder's file naming "
                             "the current session): choose another");
    if (exists(id)) throw conflict("session '" + id + "' exists already");
    std::optional<capture::SessionStore> created;
    try {
      created.emplace(capture::SessionStore::create(root, id, command.material));
    } catch (const io::IoError&) {
      // A folder left without its session.json (a full disk) is no session, `session list` leaves
      // it out, yet it kept the id taken ("exists already") once there was space again. It was
      // made just now and holds nothing.
      if (!fs::exists(root / id / "session.json")) {
        std::error_code ignored;
        fs::remove_all(root / id, ignored);
      }
      throw;
    }
    makeCurrent(std::move(*created));
    return sessionReply();
  }

  json run(const control::SessionList&) {
    json sessions = json::array();
    for (const capture::SessionInfo& info : capture::SessionStore::list(root)) {
      control::SessionListEntry entry{info.id, info.material, info.createdUtc,
                                      session && session->info().id == info.id, std::nullopt};
      if (!info.damage.empty()) entry.damaged = info.damage;
      sessions.push_back(control::toJson(entry));
    }
    return {{"sessions", std::move(sessions)}};
  }

  json run(const control::SessionShow& command) {
    std::optional<capture::SessionStore> other;
    control::SessionView shown = sessionView(target(command.id, other));
    shown.current = !other.has_value();
    return control::toJson(shown);
  }

  json run(const control::SessionResume& command) {
    if (session && session->info().id == command.id) return sessionReply();
    requireNoSweep("switch sessions");
    if (!exists(command.id)) throw noSuchSession(command.id);
    makeCurrent(capture::SessionStore::open(root, command.id));
    return sessionReply();
  }

  json run(const control::SessionDelete& command) {
    const bool isCurrent = session && session->info().id == command.id;
    if (isCurrent) requireNoSweep("delete the current session");
    if (!exists(command.id)) throw noSuchSession(command.id);
    if (isCurrent) {
      session.reset();
      std::error_code ignored;
      fs::remove(currentFile(), ignored);
    }
    capture::SessionStore::remove(root, command.id);
    return {{"deleted", command.id}};
  }

  json run(const control::SweepStart& command) {
    capture::SessionStore& store = current();
    if (sweep) {
      if (sweep->slice == command.slice && sweep->paused) {
        sweep->resume();
        lastError.clear();
        return sweepReply();
      }
      throw conflict("sweep " + toString(sweep->slice) + " is " + sweep->stateWord() +
                     ": `slicecap sweep stop` first");
    }
    store.recordSweepStarted(command.slice);
    sweep.emplace(command.slice);
    lastError.clear();
    return sweepReply();
  }

  json run(const control::SweepStop&) {
    capture::SessionStore& store = current();
    if (!sweep) throw conflict("no sweep is running");
    store.recordSweepStopped(sweep->slice);
    control::SweepView stopped = sweep->view(store);
    stopped.state = "stopped";
    sweep.reset();
    lastError.clear();  // it told why this sweep paused
    return control::toJson(stopped);
  }

  json run(const control::SweepRedo& command) {
    capture::SessionStore& store = current();
    if (sweep && sweep->slice != command.slice)
      throw conflict("sweep " + toString(sweep->slice) +
                     " is in progress: `slicecap sweep stop` first");
    store.redo(command.slice);
    ++samplesVersion;
    if (!sweep) store.recordSweepStarted(command.slice);
    sweep.emplace(command.slice);
    lastError.clear();
    return sweepReply();
  }

  json run(const control::Status&) { return control::toJson(statusView()); }

  // The tables' commands and the status (below the class).
  json run(const control::Reconstruct& command);
  json run(const control::Export& command);
  control::StatusView statusView() const;
};

json SessionManager::State::run(const control::Reconstruct& command) {
  if (capturing()) throw conflict("a sweep is running: `slicecap sweep stop` first");
  std::optional<capture::SessionStore> other;
  capture::SessionStore& store = target(command.id, other);
  const fs::path path = exporter.reconstruct(store, store.slices(), command.method).path;
  return {{"session", store.info().id},
          {"method", command.method},
          {"samples", store.sampleCount()},
          {"exr", path.string()}};
}

json SessionManager::State::run(const control::Export& command) {
  std::optional<capture::SessionStore> other;
  capture::SessionStore& store = target(command.id, other);
  const fs::path directory =
      command.directory.empty() ? store.directory() / "export" : fs::path(command.directory);
  ExportConditions conditions;
  if (capturing()) conditions.sweepRunning = sweep->slice;
  conditions.capturingIntoSession = capturing() && session && &store == &*session;
  return control::toJson(exporter.exportSession(store, directory, command.method, conditions));
}

control::StatusView SessionManager::State::statusView() const {
  control::StatusView status;
  if (session) {
    status.session = statusSessionView(*session);
    status.isotropy = isotropy.verdict(*session, samplesVersion, capturing());
    const auto sweeping = sweep ? std::optional(sweep->slice) : std::nullopt;
    status.passAgain = passAgainView(*session, sweeping, passAgain);
    status.cellTextures = cellTextureView(*session, sweeping, passAgain);
  }
  if (sweep) status.sweep = sweep->view(*session);
  status.next = nextStep(session ? &*session : nullptr, sweep ? &*sweep : nullptr,
                         status.isotropy, passAgain);
  if (!lastError.empty()) status.error = lastError;
  return status;
}

SessionManager::SessionManager(fs::path storageRoot, ReconstructFunction reconstruct,
                               PreviewFunction preview, IsotropyFunction isotropy,
                               MaterialFunction material)
    : state_(std::make_unique<State>(
          std::move(storageRoot),
          SessionExporter(std::move(reconstruct), std::move(preview), std::move(material)),
          std::move(isotropy))) {
  std::ifstream current(state_->currentFile());
  std::string id;
  if (current >> id && isValidSessionId(id) && state_->exists(id)) {
    // A current session that cannot be read (a damaged session.json or journal record) must not
    // keep the daemon from starting, or no session at all could be captured: it stays on disk as
    // it is, and the status names it until another session is made current.
    std::optional<capture::SessionStore> store;
    try {
      store.emplace(capture::SessionStore::open(state_->root, id));
    } catch (const std::exception& unreadable) {
      state_->lastError = "the current session '" + id +
                          "' cannot be opened: " + unreadable.what() +
                          " (nothing was changed on disk; `slicecap session new MATERIAL` or "
                          "`slicecap session resume ID` goes on with another)";
    }
    if (store) state_->makeCurrent(std::move(*store));
  }
}

SessionManager::~SessionManager() = default;

std::variant<json, control::ProtocolError> SessionManager::handle(const control::Command& command) {
  try {
    return std::visit([this](const auto& c) { return state_->run(c); }, command);
  } catch (const RequestError& refusal) {
    return control::ProtocolError{refusal.code(), refusal.what(), std::nullopt};
  } catch (const io::IoError& error) {
    return control::ProtocolError{control::ErrorCode::StorageError, error.what(), std::nullopt};
  } catch (const std::exception& error) {
    return control::ProtocolError{control::ErrorCode::Internal, error.what(), std::nullopt};
  }
}

bool SessionManager::capturing() const {
  return state_->capturing();
}

std::optional<SliceId> SessionManager::sweepSlice() const {
  if (!state_->sweep) return std::nullopt;
  return state_->sweep->slice;
}

std::optional<fs::path> SessionManager::sessionDirectory() const {
  if (!state_->session) return std::nullopt;
  return state_->session->directory();
}

bool SessionManager::acceptSample(const capture::FrameSample& sample) {
  if (!capturing()) return false;
  try {
    state_->session->recordSample(state_->sweep->slice, sample);
    ++state_->samplesVersion;
  } catch (const io::IoError& error) {
    // Nothing half-written counts (the journal rolls a failed append back); the sweep waits for
    // the person to free space and start it again.
    state_->sweep->pause(std::string("storage error: ") + error.what() + "; free space, then `" +
                         startCommand(state_->sweep->slice) + "` continues");
    state_->lastError = error.what();
    return false;
  } catch (const capture::CaptureError& error) {
    // A sample the journal could not replay (an HDR reading that is not finite, say): that frame
    // is lost, counted as bad_frame and logged; the sweep and its other samples go on.
    std::cerr << "slicecapd: a sample was not recorded: " << error.what() << "\n";
    rejectFrame(capture::RejectReason::BadFrame);
    return false;
  }
  ++state_->sweep->acceptedThisRun;
  return true;
}

void SessionManager::rejectFrame(capture::RejectReason reason) {
  if (state_->sweep) ++state_->sweep->rejected[std::string(toString(reason))];
}

void SessionManager::noteViewElevationErrorDeg(double errorDeg) {
  if (state_->sweep) state_->sweep->viewElevationErrorDeg = errorDeg;
}

void SessionManager::pauseSweep(const std::string& reason) {
  if (!state_->sweep) return;
  state_->sweep->pause(reason + "; `" + startCommand(state_->sweep->slice) + "` continues");
  state_->lastError = reason;
}

std::optional<std::uint64_t> SessionManager::nextRecordNumber() const {
  return state_->session ? std::optional(state_->session->nextRecordNumber()) : std::nullopt;
}

bool SessionManager::refuseSweep(const SliceId& slice, const std::string& reason,
                                 std::uint64_t firstRecord,
                                 std::optional<capture::RunTextureFrames> textureFrames) {
  if (!state_->session) return false;
  ++state_->samplesVersion;
  const RefusalOutcome refused =
      refuseSlice(*state_->session, slice, reason, firstRecord, textureFrames);
  // After the reason of a pause that ended the run, if one did: both are said, in their order.
  addToError(refused.said);
  return refused.recorded;
}

std::vector<capture::SweepRefusal> SessionManager::refusals() const {
  if (!state_->session) return {};
  return state_->session->refusals();
}

void SessionManager::addToError(const std::string& sentence) {
  std::string& error = state_->lastError;
  if (!sentence.empty()) error = error.empty() ? sentence : error + "; " + sentence;
}

std::optional<control::SweepView> SessionManager::sweepView() const {
  if (!state_->sweep) return std::nullopt;
  return state_->sweep->view(*state_->session);
}

control::StatusView SessionManager::statusView() const {
  return state_->statusView();
}

json SessionManager::status() const {
  return control::toJson(state_->statusView());
}

}  // namespace slicecap::daemon
