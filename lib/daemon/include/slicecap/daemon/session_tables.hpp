// The daemon's third collaborator: how a session's samples become tables (a reconstruction, its
// preview, the fitted material of an export) and the isotropy verdict. lib/rig implements it with
// lib/methods, lib/prior, lib/render and lib/material_export.
#pragma once

#include <filesystem>
#include <string>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/daemon/session_exporter.hpp"
#include "slicecap/daemon/session_manager.hpp"

namespace slicecap::daemon {

/// \brief The computations behind `reconstruct`, `export` and the status's isotropy line. Only
/// reconstruct is required: a rig without the others exports no preview and no material, and its
/// status never says the axial sweeps can be skipped. Called on the event loop.
class SessionTables {
 public:
  virtual ~SessionTables() = default;

  /// \brief A full table from a session's slices (ReconstructFunction says what it must do).
  virtual Abrdf reconstruct(const SliceSet& slices, const std::string& method) = 0;

  /// \brief Whether exports get a PNG preview of each table (preview is then called).
  virtual bool writesPreviews() const { return false; }
  /// \brief Writes a PNG preview of `table` (PreviewFunction).
  virtual void preview(const Abrdf& table, const std::filesystem::path& pngPath);

  /// \brief Whether the status runs the isotropy test (isotropy is then called).
  virtual bool testsIsotropy() const { return false; }
  /// \brief The isotropy test on the four diagonal sweeps (IsotropyFunction).
  virtual IsotropyAssessment isotropy(const SliceSet& slices);

  /// \brief Whether exports carry the first table's fitted material (material is then called).
  virtual bool fitsMaterial() const { return false; }
  /// \brief The fitted material of an exported table (MaterialFunction).
  virtual ExportedMaterial material(const Abrdf& table, const std::string& tableName);
};

}  // namespace slicecap::daemon
