// One typed name per reconstruction method: its command-line name, its `slicecap:method` value in
// an EXR (and the isotropic form's), and which slices it reads.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "slicecap/core/slice.hpp"

namespace slicecap::methods {

/// \brief Every reconstruction method, in the order --help lists them.
/// B and Prior read each bin's window-centre reading, as the paper does; BCells and PriorCells are
/// the same methods on each bin's value from the window cells nearest the bin centre in angle
/// (Slice::cellSamples, docs/method.md §9.4).
enum class MethodId { B, A, Uniform, AGamma, UniformGamma, Halfway, Prior, BCells, PriorCells };

/// \brief Which samples a method reconstructs from.
enum class SliceSubset {
  /// The axial and diagonal slices at 30/30, 30/75, 75/30, 75/75 (docs/method.md §2.2); in the
  /// isotropic form (eq. 5) the four diagonal ones.
  EveryMeasuredSlice,
  /// Any subset of the slices (the prior fills in the rest).
  AnySubset,
  /// Point samples at their own directions, e.g. `slicecap sample --uniform 13` (§6.3).
  PointSamples,
};

/// \brief A method's entry in the registry's table.
struct MethodInfo {
  MethodId id;
  std::string_view cliName;  ///< `--method b`, the protocol's "method", abrdf-<name>.exr
  std::string_view exrName;  ///< `slicecap:method` of the EXR, e.g. "B"
  /// `slicecap:method` of the isotropic form, e.g. "B-isotropic"; empty when the method has none
  /// (it ignores --isotropic and writes exrName).
  std::string_view isotropicExrName;
  SliceSubset reads;
};

/// \brief Whether `id` reads the slices' values from the window cells (SliceSet::cellReading):
/// b-cells and prior-cells.
constexpr bool readsCellSamples(MethodId id) {
  return id == MethodId::BCells || id == MethodId::PriorCells;
}

/// \brief The learned prior on the same reading as `id` (prior-cells for a method on the window
/// cells, prior otherwise): what reads any subset of the slices in its place.
constexpr MethodId priorOfSameReading(MethodId id) {
  return readsCellSamples(id) ? MethodId::PriorCells : MethodId::Prior;
}

/// \brief The table, one entry per MethodId in enum order.
std::span<const MethodInfo> methodTable();

/// \brief The entry of `id`.
const MethodInfo& methodInfo(MethodId id);

/// \brief The method whose cliName is `name`; std::nullopt when none is.
std::optional<MethodId> parseMethodName(std::string_view name);

/// \brief The method whose cliName is `name`; MethodError "unknown method 'x' (known: b, a, ...)".
MethodId methodNamed(std::string_view name);

/// \brief The CLI name of `id`, e.g. "b".
std::string cliName(MethodId id);

/// \brief "b, a, ..." for help texts and messages.
std::string methodNames();

/// \brief The `slicecap:method` value both writers (`slicecap reconstruct` and slicecapd's
/// reconstruct and export) put in an EXR made by `id` in this form: "B", "B-isotropic", ...; a
/// method without an isotropic form writes its exrName either way.
std::string exrMethodValue(MethodId id, bool isotropic);

/// \brief What a `slicecap:method` value says. `isotropic` is std::nullopt when the value does
/// not tell: older slicecapd exports wrote the CLI name ("b", "a-gamma"), also for the isotropic
/// form.
struct ExrMethod {
  MethodId id;
  std::optional<bool> isotropic;
};

/// \brief Reads a `slicecap:method` value: the current ones (exrMethodValue) and the CLI names
/// older slicecapd exports wrote. "halfway" and "prior" are read as the non-isotropic form (an
/// older export's "halfway" of a session without axial sweeps was the isotropic one). std::nullopt
/// for a value no method writes (e.g. "analytic", `slicecap generate`'s).
std::optional<ExrMethod> parseExrMethodValue(std::string_view value);

/// \brief Whether slicecapd reconstructs a session's `slices` with the isotropic form of `id`: a
/// session without axial sweeps (an isotropic material, its operator stopped after the diagonal
/// ones) gives the methods that read every measured slice their isotropic form (eq. 5); the prior
/// reads any subset as it is and still looks for anisotropy in the mixed-elevation diagonal slices.
bool sessionTakesIsotropicForm(MethodId id, const SliceSet& slices);

}  // namespace slicecap::methods
