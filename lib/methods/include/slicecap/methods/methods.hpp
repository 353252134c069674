// The reconstruction methods: each MethodId's run on a SliceSet, with what it reports.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/methods/method_id.hpp"
#include "slicecap/recon/method_a.hpp"
#include "slicecap/recon/slice_sum.hpp"

namespace slicecap::methods {

/// \brief Options every method receives; a method ignores what does not apply to it.
struct MethodOptions {
  bool isotropic = false;  ///< only the diagonal slices are measured (eq. 5)
  recon::TorusRule torusRule = recon::TorusRule::FundamentalSquare;
  /// \brief The shared RBF machinery of a and uniform (and their -gamma variants, which force
  /// valueGamma 2.2): Method A's defaults unless an RBF spec says otherwise (rbf_spec.hpp).
  recon::RbfParams rbf = recon::MethodAParams{}.rbf;
  recon::OnionFrame onionFrame = recon::MethodAParams{}.frame;
  /// \brief prior-cells fits every window cell as a point, one frame's cells as a group
  /// (prior::PriorParams::fitEveryCell); false: each bin's value from the cells. The default
  /// since it beat one value per bin in 21 of 24 one-exposure and 19 of 24 HDR sessions of the
  /// eight anisotropic materials and is within the window mean on the woven at every scale
  /// (docs/method.md §9.4, "The prior on every cell"); slices without cell frames (a CSV) are
  /// fitted per bin either way.
  bool priorFitsEveryCell = true;
  /// \brief With priorFitsEveryCell: one frame's cells by generalised least squares with a random
  /// frame effect (prior::PriorParams::frameAsOneSample false) instead of one sample per frame.
  bool priorCellFrameEffect = false;
};

/// \brief What a method produced: the table and what a person or a script should know about it.
struct MethodRun {
  Abrdf table;
  std::string exrMethodName;          ///< `slicecap:method` of the EXR: exrMethodValue()
  std::vector<std::string> warnings;  ///< printed on stderr (e.g. a fit that did not converge)
  std::vector<std::string> lines;     ///< a human summary, printed on stdout
  nlohmann::json details;             ///< the same for --json
};

/// \brief What a method reconstructs from, so that `eval` can simulate its capture.
enum class Acquisition {
  Slices,         ///< the 8 slices, 168 samples (docs/method.md §2.2)
  UniformGrid13,  ///< 13 light x 13 view directions, 169 point samples (docs/method.md §6.3)
};

/// \brief A method: its entry in the table, a summary for --help and its run. `run` throws (e.g.
/// recon::ReconstructionError naming a missing slice) when the samples cannot give a table.
struct Method {
  MethodId id;
  std::string name;  ///< methodInfo(id).cliName
  std::string summary;
  std::function<MethodRun(const SliceSet&, const MethodOptions&)> run;
  Acquisition acquisition = Acquisition::Slices;
};

/// \brief Every method, in MethodId's order (the order --help lists them).
const std::vector<Method>& reconstructionMethods();

/// \brief The method `id`.
const Method& findMethod(MethodId id);

/// \brief The method of this CLI name; MethodError listing the known names otherwise.
const Method& findMethod(const std::string& name);

/// \brief One line per method, "  name     summary", names padded to one column, for --help.
std::string methodHelpLines();

/// \brief The table slicecapd makes of a session's `slices` with `id`: the form
/// sessionTakesIsotropicForm() gives, default options otherwise. The EXR's `slicecap:method` is
/// exrMethodValue(id, sessionTakesIsotropicForm(id, slices)). Throws what the method throws.
MethodRun runForSession(MethodId id, const SliceSet& slices);

}  // namespace slicecap::methods
