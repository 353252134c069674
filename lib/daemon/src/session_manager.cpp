// Sessions and sweeps behind the control protocol: every change durable before its reply.
#include "slicecap/daemon/session_manager.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <system_error>

#include "slicecap/core/version.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/file_set.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/methods/method_id.hpp"

namespace slicecap::daemon {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// The `slicecap:method` of a table the session's `slices` gave with the method named `method`:
// the value `slicecap reconstruct` writes for the same form (methods::exrMethodValue). A name the
// registry does not know (only a test's stand-in reconstruction accepts one) is written as it is.
std::string exrMethodValue(const std::string& method, const SliceSet& slices) {
  const std::optional<methods::MethodId> id = methods::parseMethodName(method);
  if (!id) return method;
  return methods::exrMethodValue(*id, methods::sessionTakesIsotropicForm(*id, slices));
}

// Thrown inside this file only, turned into a ProtocolError by handle().
struct Refusal {
  ErrorCode code;
  std::string message;
};

constexpr int kBinsPerSlice = 24;
// Bins each diagonal slice needs before the isotropy test's "isotropic" is believed (isotropyJson).
constexpr int kIsotropyMinBins = 16;
// A session's reconstructed tables: <session>/abrdf-<method>.exr.
constexpr std::string_view kTablePrefix = "abrdf-";

std::string utcNow(const char* format) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, format, &utc);
  return text;
}

json sliceJson(const SliceId& slice) {
  return {{"name", toString(slice)},
          {"kind", std::string(toString(slice.kind))},
          {"theta_i", slice.elevations.thetaIDeg},
          {"theta_v", slice.elevations.thetaVDeg}};
}

std::string startCommand(const SliceId& slice) {
  return "slicecap sweep start " + std::string(toString(slice.kind)) + " " +
         std::to_string(slice.elevations.thetaIDeg) + " " +
         std::to_string(slice.elevations.thetaVDeg);
}

json slicesJson(const capture::SessionStore& store) {
  json slices = json::array();
  for (const SliceId& slice : sweepOrder()) {
    const capture::AzimuthBins& bins = store.bins(slice);
    json entry = sliceJson(slice);
    entry["samples"] = store.sampleCount(slice);
    entry["bins_filled"] = bins.filledCount();
    if (const std::size_t setAside = store.setAsideCount(slice); setAside > 0)
      entry["samples_set_aside"] = setAside;
    if (store.damaged(slice)) entry["damaged"] = true;
    slices.push_back(std::move(entry));
  }
  return slices;
}

// What replaying the journal could not tell for sure: each with the file and line in its message.
json journalDamageJson(const capture::SessionStore& store) {
  json damage = json::array();
  for (const capture::JournalDamage& d : store.damage()) {
    json slices = json::array();
    for (const SliceId& slice : d.slicesSetAside)
      slices.push_back(toString(slice));
    damage.push_back({{"line", d.line},
                      {"message", d.message},
                      {"slices_set_aside", std::move(slices)},
                      {"samples_set_aside", d.samplesSetAside},
                      {"samples_lost", d.samplesLost}});
  }
  return damage;
}

json sessionJson(const capture::SessionStore& store) {
  const capture::SessionInfo& info = store.info();
  json session = {{"id", info.id},
                  {"material", info.material},
                  {"created", info.createdUtc},
                  {"directory", store.directory().string()},
                  {"samples", store.sampleCount()},
                  {"slices", slicesJson(store)}};
  if (store.recovery().tornTailBytes > 0)
    session["torn_tail_bytes_dropped"] = store.recovery().tornTailBytes;
  if (!store.recovery().corruptLines.empty())
    session["corrupt_journal_lines"] = store.recovery().corruptLines;
  if (json damage = journalDamageJson(store); !damage.empty())
    session["journal_damage"] = std::move(damage);
  return session;
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

std::string defaultExportMethod(const SliceSet& slices) {
  for (const SliceId& slice : sweepOrder()) {
    const Slice* measured = slices.find(slice);
    if (!measured || measured->samples.empty()) return methods::cliName(methods::MethodId::Prior);
  }
  return methods::cliName(methods::MethodId::B);
}

struct SessionManager::State {
  struct Sweep {
    explicit Sweep(const SliceId& swept) : slice(swept) {}
    SliceId slice;
    bool paused = false;
    std::string pauseReason;
    std::size_t acceptedThisRun = 0;
    std::map<std::string, std::size_t> rejected;
    std::optional<double> viewElevationErrorDeg;
  };

  // The isotropy test's answer for one state of the samples.
  struct IsotropyAnswer {
    std::string session;
    std::uint64_t samplesVersion = 0;
    json answer;
  };

  fs::path root;
  int storageLock = -1;  // an flock on <root>/.lock held while this manager lives
  ReconstructFunction reconstruct;
  PreviewFunction preview;
  IsotropyFunction isotropy;
  MaterialFunction material;
  std::optional<capture::SessionStore> session;
  std::optional<Sweep> sweep;
  std::string lastError;
  std::uint64_t samplesVersion = 0;  // bumped whenever a session's samples may have changed
  mutable std::optional<IsotropyAnswer> isotropyAnswer;

  ~State() {
    if (storageLock >= 0) ::close(storageLock);
  }

  fs::path currentFile() const { return root / "current"; }

  // Two daemons on one storage folder would each append to the same session journal from their
  // own idea of it and lose each other's acknowledged samples; the second one is refused. The
  // lock goes with the process (also on SIGKILL), so a restart never finds a stale one.
  void lockStorage() {
    const fs::path lockFile = root / ".lock";
    storageLock = ::open(lockFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (storageLock < 0)
      throw io::IoError(lockFile.string() + ": cannot open: " + std::strerror(errno));
    if (::flock(storageLock, LOCK_EX | LOCK_NB) != 0) {
      const int lockError = errno;
      std::string holder;
      char pid[32] = {};
      if (::pread(storageLock, pid, sizeof pid - 1, 0) > 0) holder = std::string(pid);
      holder.erase(holder.find_last_not_of(" \n") + 1);
      ::close(storageLock);
      storageLock = -1;
      if (lockError == EWOULDBLOCK)
        throw io::IoError(root.string() + ": in use by another slicecapd" +
                          (holder.empty() ? std::string() : " (pid " + holder + ")") +
                          "; one daemon per storage folder");
      throw io::IoError(lockFile.string() + ": cannot lock: " + std::strerror(lockError));
    }
    // Only a refused second daemon's message reads the pid; the lock holds without it.
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(storageLock, 0) == 0) {
      [[maybe_unused]] const ssize_t written = ::pwrite(storageLock, pid.data(), pid.size(), 0);
    }
  }

  void makeCurrent(capture::SessionStore store) {
    ++samplesVersion;
    session.emplace(std::move(store));
    io::writeFileAtomically(currentFile(), session->info().id + "\n");
    sweep.reset();
    lastError.clear();  // it told of the sweep that went with the session before
    if (const std::optional<SliceId> active = session->activeSweep()) {
      sweep.emplace(*active);
      sweep->paused = true;
      sweep->pauseReason = "interrupted (the daemon stopped during this sweep); `" +
                           startCommand(*active) + "` continues it";
    }
  }

  capture::SessionStore& current() {
    if (!session)
      throw Refusal{ErrorCode::Conflict,
                    "no current session: `slicecap session new MATERIAL` "
                    "or `slicecap session resume ID`"};
    return *session;
  }

  bool exists(const std::string& id) const { return fs::is_directory(root / id); }

  void requireNoSweep(const char* what) const {
    if (sweep)
      throw Refusal{ErrorCode::Conflict, std::string("cannot ") + what + " while sweep " +
                                             toString(sweep->slice) + " is " +
                                             (sweep->paused ? "paused" : "running") +
                                             ": `slicecap sweep stop` first"};
  }

  /// The session a command names, or the current one; a temporary store for another session.
  capture::SessionStore& target(const std::optional<std::string>& id,
                                std::optional<capture::SessionStore>& other) {
    if (!id || (session && session->info().id == *id)) return current();
    if (!exists(*id)) throw Refusal{ErrorCode::NotFound, "no session '" + *id + "'"};
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

  json run(const Hello&) {
    return {{"daemon", "slicecapd"}, {"version", kVersion}, {"protocol", kProtocolVersion}};
  }

  json run(const SessionNew& command) {
    requireNoSweep("start a new session");
    const std::string id = command.id.value_or(newSessionId());
    // <root>/current names the current session: a session folder of that name could never be
    // made current (nor could any other after it, the file's place being taken).
    if (id == currentFile().filename())
      throw Refusal{ErrorCode::BadRequest, "session id '" + id +
                                               "' is reserved (the storage folder's file naming "
                                               "the current session): choose another"};
    if (exists(id)) throw Refusal{ErrorCode::Conflict, "session '" + id + "' exists already"};
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
    return sessionJson(*session);
  }

  json run(const SessionList&) {
    json sessions = json::array();
    for (const capture::SessionInfo& info : capture::SessionStore::list(root)) {
      sessions.push_back({{"id", info.id},
                          {"material", info.material},
                          {"created", info.createdUtc},
                          {"current", session && session->info().id == info.id}});
      if (!info.damage.empty()) sessions.back()["damaged"] = info.damage;
    }
    return {{"sessions", std::move(sessions)}};
  }

  json run(const SessionShow& command) {
    std::optional<capture::SessionStore> other;
    json shown = sessionJson(target(command.id, other));
    shown["current"] = !other.has_value();
    return shown;
  }

  json run(const SessionResume& command) {
    if (session && session->info().id == command.id) return sessionJson(*session);
    requireNoSweep("switch sessions");
    if (!exists(command.id)) throw Refusal{ErrorCode::NotFound, "no session '" + command.id + "'"};
    makeCurrent(capture::SessionStore::open(root, command.id));
    return sessionJson(*session);
  }

  json run(const SessionDelete& command) {
    const bool isCurrent = session && session->info().id == command.id;
    if (isCurrent) requireNoSweep("delete the current session");
    if (!exists(command.id)) throw Refusal{ErrorCode::NotFound, "no session '" + command.id + "'"};
    if (isCurrent) {
      session.reset();
      std::error_code ignored;
      fs::remove(currentFile(), ignored);
    }
    capture::SessionStore::remove(root, command.id);
    return {{"deleted", command.id}};
  }

  json run(const SweepStart& command) {
    capture::SessionStore& store = current();
    if (sweep) {
      if (sweep->slice == command.slice && sweep->paused) {
        sweep->paused = false;
        sweep->pauseReason.clear();
        lastError.clear();
        return sweepJson();
      }
      throw Refusal{ErrorCode::Conflict, "sweep " + toString(sweep->slice) + " is " +
                                             (sweep->paused ? "paused" : "running") +
                                             ": `slicecap sweep stop` first"};
    }
    store.recordSweepStarted(command.slice);
    sweep.emplace(command.slice);
    lastError.clear();
    return sweepJson();
  }

  json run(const SweepStop&) {
    capture::SessionStore& store = current();
    if (!sweep) throw Refusal{ErrorCode::Conflict, "no sweep is running"};
    store.recordSweepStopped(sweep->slice);
    json stopped = sweepJson();
    stopped["state"] = "stopped";
    sweep.reset();
    lastError.clear();  // it told why this sweep paused
    return stopped;
  }

  json run(const SweepRedo& command) {
    capture::SessionStore& store = current();
    if (sweep && sweep->slice != command.slice)
      throw Refusal{ErrorCode::Conflict, "sweep " + toString(sweep->slice) +
                                             " is in progress: `slicecap sweep stop` first"};
    store.redo(command.slice);
    ++samplesVersion;
    if (!sweep) store.recordSweepStarted(command.slice);
    sweep.emplace(command.slice);
    lastError.clear();
    return sweepJson();
  }

  json run(const Status&) { return statusJson(); }

  json run(const Reconstruct& command) {
    if (sweep && !sweep->paused)
      throw Refusal{ErrorCode::Conflict, "a sweep is running: `slicecap sweep stop` first"};
    std::optional<capture::SessionStore> other;
    capture::SessionStore& store = target(command.id, other);
    const fs::path path = reconstructInto(store, store.slices(), command.method).path;
    return {{"session", store.info().id},
            {"method", command.method},
            {"samples", store.sampleCount()},
            {"exr", path.string()}};
  }

  json run(const Export& command) {
    std::optional<capture::SessionStore> other;
    capture::SessionStore& store = target(command.id, other);
    const fs::path directory =
        command.directory.empty() ? store.directory() / "export" : fs::path(command.directory);
    // One reading of the samples serves every table, the CSV and the texture's slices.
    const SliceSet slices = store.slices();
    // Every table afresh from the samples as they are now: a table an earlier export or
    // reconstruct left in the session's folder may predate later sweeps or a redo. The asked (or
    // default) method first; a failure there refuses the export. An earlier table that the
    // samples can no longer give (a redo emptied a slice it needs) is removed with its exported
    // copies, with a warning, rather than exported stale.
    std::vector<std::string> methods{command.method.value_or(defaultExportMethod(slices))};
    for (const fs::directory_entry& entry : fs::directory_iterator(store.directory())) {
      const std::string name = entry.path().filename().string();
      if (entry.path().extension() != ".exr" || name.rfind(kTablePrefix, 0) != 0) continue;
      const std::string method = entry.path().stem().string().substr(kTablePrefix.size());
      if (std::find(methods.begin(), methods.end(), method) == methods.end())
        methods.push_back(method);
    }
    std::vector<SessionTable> tables;
    json warnings = json::array();
    for (std::size_t m = 0; m < methods.size(); ++m) {
      try {
        tables.push_back(reconstructInto(store, slices, methods[m]));
      } catch (const Refusal& refusal) {
        if (m == 0) throw;
        // Its copies in the export folder go with the other stale ones below.
        const std::string name = std::string(kTablePrefix) + methods[m] + ".exr";
        std::error_code ignored;  // a table that is not there is what we want
        fs::remove(store.directory() / name, ignored);
        warnings.push_back(name + " (made from earlier samples) removed: " + refusal.message);
      }
    }

    // One set, replaced as a whole (io::replaceFileSet): a failed export leaves the folder's
    // previous export as it was, no link in the folder is written through, and only tables an
    // earlier export of this session listed in its manifest are removed as stale.
    const std::string& id = store.info().id;
    std::vector<io::FileSetEntry> entries;
    for (const SessionTable& table : tables) {
      const std::string name = id + "-" + table.path.filename().string();
      entries.push_back({name, [&table](const fs::path& path) {
                           std::error_code copyError;
                           fs::copy_file(table.path, path, copyError);
                           if (copyError)
                             throw io::IoError(path.string() +
                                               ": cannot write: " + copyError.message());
                         }});
      if (preview)
        entries.push_back({fs::path(name).replace_extension(".png").string(),
                           [this, &table](const fs::path& path) { preview(table.values, path); }});
    }
    // The first (asked or default) table's fitted material. A fit takes about a second here and
    // several on a Pi: not while a sweep's frames wait on this thread.
    const bool sweepRunning = sweep && !sweep->paused;
    std::optional<ExportedMaterial> fitted;
    json materialNote;
    if (material && !tables.empty()) {
      const std::string tableName = id + "-" + tables.front().path.filename().string();
      if (sweepRunning) {
        materialNote = "not fitted while sweep " + toString(sweep->slice) +
                       " runs: `slicecap sweep stop` (or let it pause), then export again";
      } else {
        try {
          fitted = material(tables.front().values, tableName);
          materialNote = fitted->summary;
        } catch (const std::exception& error) {
          warnings.push_back(std::string("no fitted material: ") + error.what());
        }
      }
    }
    if (fitted)
      for (const ExportedMaterialFile& file : fitted->files)
        entries.push_back({id + file.suffix, file.write});
    entries.push_back({id + "-slices.csv",
                       [&slices](const fs::path& path) { io::writeSliceCsv(path, slices); }});
    json summary = sessionJson(store);
    summary["exported"] = utcNow("%Y-%m-%dT%H:%M:%SZ");
    summary["slicecap_version"] = kVersion;
    entries.push_back({id + "-summary.json", [&summary](const fs::path& path) {
                         io::writeFileAtomically(path, summary.dump(2) + "\n");
                       }});
    json files = json::array();
    for (const fs::path& file : io::replaceFileSet(directory, id, entries))
      files.push_back(file.string());
    // What the journal could not tell for sure goes with every export of the session.
    for (const capture::JournalDamage& damage : store.damage())
      warnings.push_back(damage.message);
    json reply = {{"session", store.info().id},
                  {"directory", directory.string()},
                  {"files", files},
                  {"method", methods.front()}};
    if (!materialNote.is_null()) reply["material"] = materialNote;
    if (!warnings.empty()) reply["warnings"] = std::move(warnings);
    // A running sweep adds and replaces texture frames while the client copies: refused, not
    // half copied. A paused or stopped sweep leaves the folder still.
    const bool capturingIntoIt = sweep && !sweep->paused && session && &store == &*session;
    if (capturingIntoIt && fs::is_directory(store.directory() / kTextureFolder))
      reply["texture_skipped"] = "sweep " + toString(sweep->slice) +
                                 " is capturing into the texture: `slicecap sweep stop` (or let "
                                 "it pause), then export again for the texture";
    else if (const std::optional<fs::path> texture = exportTexture(store, slices))
      reply["texture"] = texture->string();
    return reply;
  }

  /// The session's texture folder, if it has one, with the session's window-average slices
  /// written into it (slices.csv: the BTF's average ABRDF is made from them). Not copied here: the
  /// client copies it (`slicecap export` to DIR/<id>-texture), as it can be hundreds of MB.
  std::optional<fs::path> exportTexture(const capture::SessionStore& store,
                                        const SliceSet& slices) {
    const fs::path texture = store.directory() / kTextureFolder;
    if (!fs::is_directory(texture)) return std::nullopt;
    std::ostringstream csv;
    io::writeSliceCsv(csv, slices);
    io::writeFileAtomically(texture / "slices.csv", csv.str());
    return texture;
  }

  // A table made from a session's samples, written to <session>/abrdf-<method>.exr.
  struct SessionTable {
    fs::path path;
    Abrdf values;
  };

  SessionTable reconstructInto(const capture::SessionStore& store, const SliceSet& slices,
                               const std::string& method) {
    if (slices.empty())
      throw Refusal{ErrorCode::Conflict,
                    "session '" + store.info().id + "' has no samples to reconstruct from"};
    Abrdf table;
    try {
      table = reconstruct(slices, method);
    } catch (const std::exception& error) {
      std::string message = "reconstruction with method '" + method + "' failed: " + error.what();
      if (methods::parseMethodName(method) != methods::MethodId::Prior)
        message += " (`--method " + methods::cliName(methods::MethodId::Prior) +
                   "` reconstructs from any subset of the slices)";
      throw Refusal{ErrorCode::Conflict, message};
    }
    const fs::path path = store.directory() / (std::string(kTablePrefix) + method + ".exr");
    io::writeAbrdfExr(
        path, table,
        {{"method", exrMethodValue(method, slices)},
         {"material", store.info().material},
         {"session", store.info().id}});
    return {path, std::move(table)};
  }

  json sweepJson() const {
    const capture::AzimuthBins& bins = session->bins(sweep->slice);
    json rejected = json::object();
    for (const auto& [reason, count] : sweep->rejected)
      rejected[reason] = count;
    json state = {{"slice", sliceJson(sweep->slice)},
                  {"state", sweep->paused ? "paused" : "capturing"},
                  {"bins", bins.filled()},
                  {"bins_filled", bins.filledCount()},
                  {"samples", session->sampleCount(sweep->slice)},
                  {"accepted_this_run", sweep->acceptedThisRun},
                  {"rejected", std::move(rejected)},
                  {"view_elevation_error_deg", nullptr}};
    if (sweep->paused) state["pause_reason"] = sweep->pauseReason;
    if (sweep->viewElevationErrorDeg)
      state["view_elevation_error_deg"] = *sweep->viewElevationErrorDeg;
    return state;
  }

  std::string nextStep() const {
    if (!session) return "slicecap session new MATERIAL";
    if (sweep) {
      if (sweep->paused) return sweep->pauseReason;
      const int filled = session->bins(sweep->slice).filledCount();
      if (filled >= kBinsPerSlice) return "all 24 bins filled: slicecap sweep stop";
      return "keep sweeping " + toString(sweep->slice) + ": " + std::to_string(filled) +
             " of 24 bins filled";
    }
    const std::string exportCommand = "slicecap export " + session->info().id + " -o DIR";
    // A slice with samples counts as swept: a hand-held sweep seldom fills all 24 bins, and a
    // hint that waits for them never moves on. The sparsest slice is named at the end.
    std::optional<SliceId> axial;
    for (const SliceId& slice : sweepOrder()) {
      if (swept(slice)) continue;
      if (slice.kind == SliceKind::Diagonal) return startCommand(slice);
      axial = slice;
      break;
    }
    if (!axial) {
      std::optional<SliceId> sparsest;
      for (const SliceId& slice : sweepOrder())
        if (!sparsest || filledBins(slice) < filledBins(*sparsest)) sparsest = slice;
      std::string hint = "every slice is swept: " + exportCommand;
      if (filledBins(*sparsest) < kBinsPerSlice)
        hint += " (the sparsest, " + toString(*sparsest) + ", has " +
                std::to_string(filledBins(*sparsest)) + " of 24 bins: `" + startCommand(*sparsest) +
                "` adds to it)";
      return hint;
    }
    const json verdict = isotropyJson();
    if (verdict.is_object() && !verdict["axial_sweeps_needed"].get<bool>())
      return "the diagonal sweeps look isotropic, the axial sweeps are not needed: " +
             exportCommand + " (to measure them anyway: " + startCommand(*axial) + ")";
    if (verdict.is_object() && verdict.contains("isotropic") && verdict["isotropic"] == false)
      return "the diagonal sweeps show anisotropy: " + startCommand(*axial);
    if (verdict.is_object() && verdict.value("informative", true) == false)
      return "cannot tell yet whether the axial sweeps are needed (" +
             verdict["reason"].get<std::string>() + "): " + startCommand(*axial) + " measures them";
    return startCommand(*axial);
  }

  int filledBins(const SliceId& slice) const { return session->bins(slice).filledCount(); }

  bool swept(const SliceId& slice) const { return session->sampleCount(slice) > 0; }

  // The isotropy test on the session's slices once each of the four diagonal ones has samples
  // (null before, or without a test): whether the axial sweeps are needed. Not only once they
  // are complete: a hand-held sweep often leaves a few bins empty, and the test reads the samples
  // at their actual angles, wherever they are.
  json isotropyJson() const {
    if (!session || !isotropy) return nullptr;
    std::optional<SliceId> sparsest;  // the diagonal slice with the fewest filled bins
    for (const SliceId& slice : sweepOrder()) {
      if (slice.kind != SliceKind::Diagonal) continue;
      if (session->sampleCount(slice) < 2) return nullptr;
      if (!sparsest || filledBins(slice) < filledBins(*sparsest)) sparsest = slice;
    }
    // While a sweep captures, the answer from before it stands: the test (two prior fits, a few
    // ms on a Pi) is not rerun on the frame loop for every status a --watch asks for.
    const bool capturing = sweep && !sweep->paused;
    if (isotropyAnswer && isotropyAnswer->session == session->info().id &&
        (isotropyAnswer->samplesVersion == samplesVersion || capturing))
      return isotropyAnswer->answer;
    json answer;
    try {
      IsotropyAssessment verdict = isotropy(session->slices());
      // "Isotropic" is believed only from well-covered diagonal slices; "anisotropic" from any.
      // Measured (the test on ideal diagonal slices keeping k random bins of 24, 5 draws, MERL
      // prior): the anisotropic analytic materials called isotropic 8, 7, 5, 5, 5 of 40 at k = 8,
      // 12, 16, 20, 24 (the 5: ward-gold-60, missed at full coverage too); isotropic held-out
      // tables called anisotropic 9, 7, 6, 5, 5 of 295. A false "isotropic" costs a wrong table, a
      // false "anisotropic" four more sweeps.
      const int fewestBins = filledBins(*sparsest);
      if (verdict.isotropic && fewestBins < kIsotropyMinBins) {
        verdict.informative = false;
        verdict.reason =
            "no anisotropy seen, but too few bins to rule it out: " + toString(*sparsest) +
            " has " + std::to_string(fewestBins) + " of 24 (" + std::to_string(kIsotropyMinBins) +
            " needed); sweep it again or measure the axial sweeps";
      }
      // Not informative: "isotropic" is the test's default, not a finding, so null (unknown).
      answer = {{"isotropic", verdict.informative ? json(verdict.isotropic) : json(nullptr)},
                {"informative", verdict.informative},
                {"axial_sweeps_needed", !(verdict.isotropic && verdict.informative)},
                {"reason", verdict.reason}};
    } catch (const std::exception& error) {
      answer = {{"error", std::string("isotropy test: ") + error.what()},
                {"axial_sweeps_needed", true}};
    }
    isotropyAnswer = IsotropyAnswer{session->info().id, samplesVersion, answer};
    return answer;
  }

  json statusJson() const {
    json status = {{"session", nullptr}, {"sweep", nullptr}, {"next", nextStep()}};
    if (session) {
      status["session"] = {{"id", session->info().id},
                           {"material", session->info().material},
                           {"samples", session->sampleCount()},
                           {"slices", slicesJson(*session)}};
      if (json damage = journalDamageJson(*session); !damage.empty())
        status["session"]["journal_damage"] = std::move(damage);
    }
    if (sweep) status["sweep"] = sweepJson();
    if (json verdict = isotropyJson(); !verdict.is_null()) status["isotropy"] = std::move(verdict);
    if (!lastError.empty()) status["error"] = lastError;
    return status;
  }
};

SessionManager::SessionManager(fs::path storageRoot, ReconstructFunction reconstruct,
                               PreviewFunction preview, IsotropyFunction isotropy,
                               MaterialFunction material)
    : state_(std::make_unique<State>()) {
  state_->root = std::move(storageRoot);
  state_->reconstruct = std::move(reconstruct);
  state_->preview = std::move(preview);
  state_->isotropy = std::move(isotropy);
  state_->material = std::move(material);
  std::error_code error;
  fs::create_directories(state_->root, error);
  if (error || !fs::is_directory(state_->root))
    throw io::IoError(state_->root.string() + ": cannot use as session storage: " +
                      (error ? error.message() : "not a folder"));
  state_->lockStorage();
  std::ifstream current(state_->currentFile());
  std::string id;
  if (current >> id && capture::isValidSessionId(id) && state_->exists(id)) {
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

std::variant<json, ProtocolError> SessionManager::handle(const Command& command) {
  try {
    return std::visit([this](const auto& c) { return state_->run(c); }, command);
  } catch (const Refusal& refusal) {
    return ProtocolError{refusal.code, refusal.message, std::nullopt};
  } catch (const io::IoError& error) {
    return ProtocolError{ErrorCode::StorageError, error.what(), std::nullopt};
  } catch (const std::exception& error) {
    return ProtocolError{ErrorCode::Internal, error.what(), std::nullopt};
  }
}

bool SessionManager::capturing() const {
  return state_->sweep && !state_->sweep->paused;
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
    state_->sweep->paused = true;
    state_->sweep->pauseReason = std::string("storage error: ") + error.what() +
                                 "; free space, then `" + startCommand(state_->sweep->slice) +
                                 "` continues";
    state_->lastError = error.what();
    return false;
  }
  ++state_->sweep->acceptedThisRun;
  return true;
}

void SessionManager::rejectFrame(const std::string& reason) {
  if (state_->sweep) ++state_->sweep->rejected[reason];
}

void SessionManager::noteViewElevationErrorDeg(double errorDeg) {
  if (state_->sweep) state_->sweep->viewElevationErrorDeg = errorDeg;
}

void SessionManager::pauseSweep(const std::string& reason) {
  if (!state_->sweep) return;
  state_->sweep->paused = true;
  state_->sweep->pauseReason = reason + "; `" + startCommand(state_->sweep->slice) + "` continues";
  state_->lastError = reason;
}

json replyOrThrow(std::variant<json, ProtocolError> reply) {
  if (auto* error = std::get_if<ProtocolError>(&reply))
    throw RequestError(error->code, error->message);
  return std::move(std::get<json>(reply));
}

json SessionManager::status() const {
  return state_->statusJson();
}

}  // namespace slicecap::daemon
