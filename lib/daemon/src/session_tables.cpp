// What a SessionTables without previews, isotropy test or material does when asked anyway: the
// daemon asks only what writesPreviews(), testsIsotropy() and fitsMaterial() say is there.
#include "slicecap/daemon/session_tables.hpp"

#include <stdexcept>

namespace slicecap::daemon {

void SessionTables::preview(const Abrdf&, const std::filesystem::path&) {
  throw std::logic_error("SessionTables::preview called on tables that write no previews");
}

IsotropyAssessment SessionTables::isotropy(const SliceSet&) {
  throw std::logic_error("SessionTables::isotropy called on tables without the isotropy test");
}

ExportedMaterial SessionTables::material(const Abrdf&, const std::string&) {
  throw std::logic_error("SessionTables::material called on tables that fit no material");
}

}  // namespace slicecap::daemon
