// A session's export as one set: tables afresh, previews, fitted material, slices CSV, summary,
// and the list of the texture's files for the client to copy.
#include "slicecap/daemon/session_exporter.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <system_error>

#include "session_report.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/daemon/sweep_decoding.hpp"
#include "slicecap/daemon/texture_sink.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/io/file_set.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/methods/method_id.hpp"

namespace slicecap::daemon {
namespace {

namespace fs = std::filesystem;

// A session's reconstructed tables: <session>/abrdf-<method>.exr.
constexpr std::string_view kTablePrefix = "abrdf-";

// The `slicecap:method` of a table the session's `slices` gave with the method named `method`:
// the value `slicecap reconstruct` writes for the same form (methods::exrMethodValue). A name the
// registry does not know (only a test's stand-in reconstruction accepts one) is written as it is.
std::string exrMethodValue(const std::string& method, const SliceSet& slices) {
  const std::optional<methods::MethodId> id = methods::parseMethodName(method);
  if (!id) return method;
  return methods::exrMethodValue(*id, methods::sessionTakesIsotropicForm(*id, slices));
}

// The asked method first, then each table an earlier export or reconstruct left in the folder.
std::vector<std::string> tableMethods(const capture::SessionStore& store, std::string asked) {
  std::vector<std::string> methods{std::move(asked)};
  for (const fs::directory_entry& entry : fs::directory_iterator(store.directory())) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".exr" || name.rfind(kTablePrefix, 0) != 0) continue;
    const std::string method = entry.path().stem().string().substr(kTablePrefix.size());
    if (std::find(methods.begin(), methods.end(), method) == methods.end())
      methods.push_back(method);
  }
  return methods;
}

void copyTable(const fs::path& table, const fs::path& copy) {
  std::error_code error;
  fs::copy_file(table, copy, error);
  if (error) throw io::IoError(copy.string() + ": cannot write: " + error.message());
}

// The files of a session's texture folder a copy needs, relative to it: temporaries, the
// folders of discarded sweeps and the frames an unjudged run replaced (held) are left out, and
// so are the frames of refused sweep runs (each such folder said in `setAside`, with its frames).
std::vector<std::string> textureFiles(const fs::path& texture, std::vector<std::string>& setAside) {
  std::vector<std::string> files;
  std::error_code error;
  fs::recursive_directory_iterator it(texture, error);
  for (const fs::recursive_directory_iterator end; !error && it != end; it.increment(error)) {
    if (it->path().extension() == io::kDiscardedSuffix ||
        it->path().extension() == io::kHeldSuffix) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->path().extension() == io::kSetAsideSuffix && it->is_directory(error)) {
      it.disable_recursion_pending();
      std::size_t frames = 0;
      for (const fs::directory_entry& file : fs::directory_iterator(it->path(), error))
        frames += file.is_regular_file(error) ? 1 : 0;
      if (frames > 0)
        setAside.push_back("texture: " + std::to_string(frames) +
                           " frames of refused sweep runs left out (kept in " +
                           fs::relative(it->path(), texture.parent_path()).string() + ")");
      continue;
    }
    if (it->is_regular_file(error) && it->path().extension() != ".tmp")
      files.push_back(fs::relative(it->path(), texture).string());
  }
  if (error) throw io::IoError(texture.string() + ": cannot read: " + error.message());
  std::sort(files.begin(), files.end());
  return files;
}

// The session's texture folder, if it has one, with the session's window-average slices written
// into it (slices.csv: the BTF's average ABRDF is made from them).
std::optional<fs::path> prepareTexture(const capture::SessionStore& store, const SliceSet& slices) {
  const fs::path texture = store.directory() / kTextureFolder;
  if (!fs::is_directory(texture)) return std::nullopt;
  std::ostringstream csv;
  io::writeSliceCsv(csv, slices);
  io::writeFileAtomically(texture / "slices.csv", csv.str());
  return texture;
}

}  // namespace

std::string defaultExportMethod(const SliceSet& slices) {
  for (const SliceId& slice : sweepOrder()) {
    const Slice* measured = slices.find(slice);
    if (!measured || measured->samples.empty())
      return methods::cliName(methods::MethodId::PriorCells);
  }
  return methods::cliName(methods::MethodId::B);
}

SessionExporter::SessionExporter(ReconstructFunction reconstruct, PreviewFunction preview,
                                 MaterialFunction material)
    : reconstruct_(std::move(reconstruct)),
      preview_(std::move(preview)),
      material_(std::move(material)) {}

SessionTable SessionExporter::reconstruct(const capture::SessionStore& store,
                                          const SliceSet& slices,
                                          const std::string& method) const {
  if (slices.empty()) {
    std::string message = "session '" + store.info().id + "' has no samples to reconstruct from";
    for (const std::string& refusal : refusalWarnings(store)) message += "; " + refusal;
    throw RequestError(control::ErrorCode::Conflict, message);
  }
  Abrdf table;
  try {
    table = reconstruct_(slices, method);
  } catch (const std::exception& error) {
    std::string message = "reconstruction with method '" + method + "' failed: " + error.what();
    // The prior of the same reading (window cells or centres) reads any subset of the slices.
    const std::optional<methods::MethodId> asked = methods::parseMethodName(method);
    const methods::MethodId prior =
        asked ? methods::priorOfSameReading(*asked) : methods::MethodId::Prior;
    if (asked != prior)
      message += " (`--method " + methods::cliName(prior) +
                 "` reconstructs from any subset of the slices)";
    throw RequestError(control::ErrorCode::Conflict, message);
  }
  const fs::path path = store.directory() / (std::string(kTablePrefix) + method + ".exr");
  io::writeAbrdfExr(path, table,
                    {{"method", exrMethodValue(method, slices)},
                     {"material", store.info().material},
                     {"session", store.info().id}});
  return {path, std::move(table)};
}

control::ExportView SessionExporter::exportSession(const capture::SessionStore& store,
                                                   const fs::path& directory,
                                                   const std::optional<std::string>& method,
                                                   const ExportConditions& conditions) const {
  // One reading of the samples serves every table, the CSV and the texture's slices.
  std::map<SliceId, capture::CellTexture> verdicts;
  const SliceSet slices = store.slices(&verdicts);
  const std::string& id = store.info().id;
  control::ExportView reply;
  reply.session = id;
  reply.directory = directory.string();
  // Every table afresh from the samples as they are now: a table an earlier export or
  // reconstruct left in the session's folder may predate later sweeps or a redo. The asked (or
  // default) method first; a failure there refuses the export. An earlier table that the samples
  // can no longer give (a redo emptied a slice it needs) is removed with its exported copies,
  // with a warning, rather than exported stale.
  const std::vector<std::string> methods =
      tableMethods(store, method.value_or(defaultExportMethod(slices)));
  reply.method = methods.front();
  std::vector<SessionTable> tables;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    try {
      tables.push_back(reconstruct(store, slices, methods[m]));
    } catch (const RequestError& refusal) {
      if (m == 0) throw;
      // Its copies in the export folder go with the other stale ones (io::replaceFileSet).
      const std::string name = std::string(kTablePrefix) + methods[m] + ".exr";
      std::error_code ignored;  // a table that is not there is what we want
      fs::remove(store.directory() / name, ignored);
      reply.warnings.push_back(name + " (made from earlier samples) removed: " + refusal.what());
    }
  }
  // One set, replaced as a whole (io::replaceFileSet): a failed export leaves the folder's
  // previous export as it was, no link in the folder is written through, and only tables an
  // earlier export of this session listed in its manifest are removed as stale.
  std::vector<io::FileSetEntry> entries;
  for (const SessionTable& table : tables) {
    const std::string name = id + "-" + table.path.filename().string();
    entries.push_back({name, [&table](const fs::path& copy) { copyTable(table.path, copy); }});
    if (preview_)
      entries.push_back({fs::path(name).replace_extension(".png").string(),
                         [this, &table](const fs::path& png) { preview_(table.values, png); }});
  }
  const std::optional<ExportedMaterial> fitted = fitMaterial(store, tables, conditions, reply);
  if (fitted)
    for (const ExportedMaterialFile& file : fitted->files)
      entries.push_back({id + file.suffix, file.write});
  entries.push_back({id + "-slices.csv",
                     [&slices](const fs::path& path) { io::writeSliceCsv(path, slices); }});
  nlohmann::json summary = control::toJson(sessionView(store));
  summary["exported"] = utcNow("%Y-%m-%dT%H:%M:%SZ");
  summary["slicecap_version"] = kVersion;
  // How each slice's window cells were read (docs/method.md §9.4): the rule the export applied.
  summary["cell_texture"] = nlohmann::json::object();
  for (const auto& [slice, texture] : verdicts)
    summary["cell_texture"][toString(slice)] = capture::toJson(texture);
  entries.push_back({id + "-summary.json", [&summary](const fs::path& path) {
                       io::writeFileAtomically(path, summary.dump(2) + "\n");
                     }});
  for (const fs::path& file : io::replaceFileSet(directory, id, entries))
    reply.files.push_back(file.string());
  // What the journal could not tell for sure goes with every export of the session.
  for (const capture::JournalDamage& damage : store.damage())
    reply.warnings.push_back(damage.message);
  // And what the sweeps' decoding checks found: samples a processed stream may have spoilt.
  for (std::string& warning : recordedDecodingWarnings(store.directory()))
    reply.warnings.push_back(std::move(warning));
  for (const std::string& refusal : refusalWarnings(store)) reply.warnings.push_back(refusal);
  addTexture(store, slices, conditions, reply);
  return reply;
}

std::optional<ExportedMaterial> SessionExporter::fitMaterial(
    const capture::SessionStore& store, const std::vector<SessionTable>& tables,
    const ExportConditions& conditions, control::ExportView& reply) const {
  if (!material_ || tables.empty()) return std::nullopt;
  // The first (asked or default) table's fitted material. A fit takes about a second here and
  // several on a Pi: not while a sweep's frames wait on this thread.
  if (conditions.sweepRunning) {
    reply.material = "not fitted while sweep " + toString(*conditions.sweepRunning) +
                     " runs: `slicecap sweep stop` (or let it pause), then export again";
    return std::nullopt;
  }
  try {
    ExportedMaterial fitted =
        material_(tables.front().values,
                  store.info().id + "-" + tables.front().path.filename().string());
    reply.material = fitted.summary;
    return fitted;
  } catch (const std::exception& error) {
    reply.warnings.push_back(std::string("no fitted material: ") + error.what());
    return std::nullopt;
  }
}

void SessionExporter::addTexture(const capture::SessionStore& store, const SliceSet& slices,
                                 const ExportConditions& conditions,
                                 control::ExportView& reply) const {
  // A running sweep adds and replaces texture frames while the client copies: refused, not half
  // copied. A paused or stopped sweep leaves the folder still.
  if (conditions.capturingIntoSession && conditions.sweepRunning &&
      fs::is_directory(store.directory() / kTextureFolder)) {
    reply.textureSkipped = "sweep " + toString(*conditions.sweepRunning) +
                           " is capturing into the texture: `slicecap sweep stop` (or let "
                           "it pause), then export again for the texture";
    return;
  }
  // Not copied on the box: the client copies the listed files (`slicecap export` to
  // DIR/<id>-texture), as the folder can be hundreds of MB.
  if (const std::optional<fs::path> texture = prepareTexture(store, slices)) {
    reply.texture = texture->string();
    std::vector<std::string> setAside;
    reply.textureFiles = textureFiles(*texture, setAside);
    for (std::string& said : setAside) reply.warnings.push_back(std::move(said));
  }
}

}  // namespace slicecap::daemon
