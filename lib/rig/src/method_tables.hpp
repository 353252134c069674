// The daemon's SessionTables on lib/methods (the reconstruction by name), lib/render (previews),
// lib/prior (the isotropy test) and lib/material_export (the exported material).
#pragma once

#include "slicecap/daemon/session_tables.hpp"

namespace slicecap::rig {

/// \brief Every table computation the daemon can ask for.
class MethodTables final : public daemon::SessionTables {
 public:
  Abrdf reconstruct(const SliceSet& slices, const std::string& method) override;
  bool writesPreviews() const override { return true; }
  void preview(const Abrdf& table, const std::filesystem::path& pngPath) override;
  bool testsIsotropy() const override { return true; }
  daemon::IsotropyAssessment isotropy(const SliceSet& slices) override;
  bool fitsMaterial() const override { return true; }
  daemon::ExportedMaterial material(const Abrdf& table, const std::string& tableName) override;
};

}  // namespace slicecap::rig
