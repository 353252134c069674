// The registry's table of names: every place that names a method reads it from here.
#include "slicecap/methods/method_id.hpp"

#include <algorithm>
#include <array>

#include "slicecap/methods/errors.hpp"

namespace slicecap::methods {
namespace {

// In MethodId's order (methodInfo indexes it). The EXR names are those
// docs/reference/file-formats.md documents and `slicecap reconstruct` has always written.
constexpr std::array<MethodInfo, 9> kTable{{
    {MethodId::B, "b", "B", "B-isotropic", SliceSubset::EveryMeasuredSlice},
    {MethodId::A, "a", "A", "A-isotropic", SliceSubset::EveryMeasuredSlice},
    {MethodId::Uniform, "uniform", "uniform-RBF", "", SliceSubset::PointSamples},
    {MethodId::AGamma, "a-gamma", "A-gamma", "A-gamma-isotropic",
     SliceSubset::EveryMeasuredSlice},
    {MethodId::UniformGamma, "uniform-gamma", "uniform-RBF-gamma", "", SliceSubset::PointSamples},
    {MethodId::Halfway, "halfway", "halfway", "halfway-isotropic",
     SliceSubset::EveryMeasuredSlice},
    {MethodId::Prior, "prior", "prior", "prior-isotropic", SliceSubset::AnySubset},
    {MethodId::BCells, "b-cells", "B-cells", "B-cells-isotropic", SliceSubset::EveryMeasuredSlice},
    {MethodId::PriorCells, "prior-cells", "prior-cells", "prior-cells-isotropic",
     SliceSubset::AnySubset},
}};

}  // namespace

std::span<const MethodInfo> methodTable() { return kTable; }

const MethodInfo& methodInfo(MethodId id) {
  const auto index = static_cast<std::size_t>(id);
  if (index >= kTable.size() || kTable[index].id != id)
    throw MethodError("method id " + std::to_string(index) + " is not in the registry");
  return kTable[index];
}

std::optional<MethodId> parseMethodName(std::string_view name) {
  for (const MethodInfo& info : kTable)
    if (info.cliName == name) return info.id;
  return std::nullopt;
}

MethodId methodNamed(std::string_view name) {
  if (const std::optional<MethodId> id = parseMethodName(name)) return *id;
  throw MethodError("unknown method '" + std::string(name) + "' (known: " + methodNames() + ")");
}

std::string cliName(MethodId id) { return std::string(methodInfo(id).cliName); }

std::string methodNames() {
  std::string names;
  for (const MethodInfo& info : kTable)
    names += (names.empty() ? "" : ", ") + std::string(info.cliName);
  return names;
}

std::string exrMethodValue(MethodId id, bool isotropic) {
  const MethodInfo& info = methodInfo(id);
  return std::string(isotropic && !info.isotropicExrName.empty() ? info.isotropicExrName
                                                                 : info.exrName);
}

std::optional<ExrMethod> parseExrMethodValue(std::string_view value) {
  // The current values first: "halfway" and "prior" are both an EXR value and a CLI name, and as
  // EXR values they say the form.
  for (const MethodInfo& info : kTable) {
    if (info.exrName == value) return ExrMethod{info.id, false};
    if (!info.isotropicExrName.empty() && info.isotropicExrName == value)
      return ExrMethod{info.id, true};
  }
  if (const std::optional<MethodId> id = parseMethodName(value))
    return ExrMethod{*id, std::nullopt};
  return std::nullopt;
}

bool sessionTakesIsotropicForm(MethodId id, const SliceSet& slices) {
  if (methodInfo(id).reads != SliceSubset::EveryMeasuredSlice) return false;
  return std::none_of(slices.slices().begin(), slices.slices().end(),
                      [](const Slice& s) { return s.id.kind == SliceKind::Axial; });
}

}  // namespace slicecap::methods
