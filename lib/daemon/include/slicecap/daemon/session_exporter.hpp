// A session's export, made in one place: its tables afresh, their previews and fitted material,
// the slices CSV, a summary and the texture's file list, written as one set (io::replaceFileSet).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/core/abrdf.hpp"

namespace slicecap::daemon {

/// \brief Reconstructs a full table from a session's slices with a named method of lib/methods
/// (slicecapd's main injects methods::runForSession), in the form the registry gives the session
/// (methods::sessionTakesIsotropicForm): the daemon names the table's `slicecap:method` by that
/// form. Throws std::exception with a message a person can act on (e.g. which slices are missing).
using ReconstructFunction = std::function<Abrdf(const SliceSet& slices, const std::string& method)>;
/// \brief Writes a PNG preview of a table (optional: export leaves the preview out without it).
using PreviewFunction =
    std::function<void(const Abrdf& table, const std::filesystem::path& pngPath)>;

/// \brief One file of an exported table's fitted material: `write` writes it to the path given,
/// whose name ends in `suffix`.
struct ExportedMaterialFile {
  std::string suffix;
  std::function<void(const std::filesystem::path&)> write;
};
/// \brief The fitted material of an exported table (material_export::sessionMaterial, injected by
/// the daemon's main): its files and a line for the reply. Throws std::exception with a message
/// when the table cannot be fitted; the export then goes on without it, saying why.
struct ExportedMaterial {
  std::vector<ExportedMaterialFile> files;
  std::string summary;
};
using MaterialFunction =
    std::function<ExportedMaterial(const Abrdf& table, const std::string& tableName)>;

/// \brief A table made from a session's samples, written to <session>/abrdf-<method>.exr.
struct SessionTable {
  std::filesystem::path path;
  Abrdf values;
};

/// \brief What a sweep is doing while the export runs.
struct ExportConditions {
  /// The running (not paused) sweep's slice, if any: the material is not fitted meanwhile (a fit
  /// takes seconds on a Pi, while frames wait on the same thread).
  std::optional<SliceId> sweepRunning;
  /// True when that sweep captures into the exported session's texture: the texture is then
  /// skipped (frames are added and replaced while the client would copy them).
  bool capturingIntoSession = false;
};

/// \brief Makes tables and exports of sessions. Refusals (no samples, a method that cannot read
/// the session's slices) throw RequestError (conflict); a store that cannot write throws
/// io::IoError naming the file.
class SessionExporter {
 public:
  /// \brief Without `preview` exports hold no PNGs; without `material`, no fitted material.
  SessionExporter(ReconstructFunction reconstruct, PreviewFunction preview = {},
                  MaterialFunction material = {});

  /// \brief Reconstructs `slices` with `method` into <session>/abrdf-<method>.exr.
  SessionTable reconstruct(const capture::SessionStore& store, const SliceSet& slices,
                           const std::string& method) const;

  /// \brief The session's export into `directory`, as one set: the asked (or default) method's
  /// table first, then every table made earlier, each made afresh from the samples as they are
  /// now; previews, the first table's fitted material, the slices CSV and a summary. An earlier
  /// table the samples can no longer give is removed, with a warning. The reply lists the files
  /// written and, with a texture, the texture folder's files for the client to copy.
  control::ExportView exportSession(const capture::SessionStore& store,
                                    const std::filesystem::path& directory,
                                    const std::optional<std::string>& method,
                                    const ExportConditions& conditions) const;

 private:
  // The first table's fitted material (its summary or why there is none goes into `reply`).
  std::optional<ExportedMaterial> fitMaterial(const capture::SessionStore& store,
                                              const std::vector<SessionTable>& tables,
                                              const ExportConditions& conditions,
                                              control::ExportView& reply) const;
  // The texture folder and its files, or why it is skipped this time.
  void addTexture(const capture::SessionStore& store, const SliceSet& slices,
                  const ExportConditions& conditions, control::ExportView& reply) const;
  ReconstructFunction reconstruct_;
  PreviewFunction preview_;
  MaterialFunction material_;
};

/// \brief The method `export` reconstructs with when none is asked for: Method B ("b", the window
/// centres) when each of the eight slices has samples, otherwise the learned prior fitted to every
/// window cell ("prior-cells"), which reads any subset (a slice without cells is read at its
/// window centres). Why these two: docs/method.md §8.2.
std::string defaultExportMethod(const SliceSet& slices);

}  // namespace slicecap::daemon
