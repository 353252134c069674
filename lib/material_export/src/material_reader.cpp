// Parses a `slicecap fit` JSON strictly: a field missing or out of range is an error naming the file
// and the field, never a default (issue 30: exports refuse a material they could not fit).
#include "slicecap/material_export/material_reader.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "slicecap/fit/material_json.hpp"
#include "slicecap/fit/sheen_albedo.hpp"

namespace slicecap::material_export {
namespace {

using json = nlohmann::json;

class Reader {
 public:
  // The document by reference: a copy of a deeply nested one recursed until the stack ran out.
  Reader(std::filesystem::path path, const json& document)
      : path_(std::move(path)), document_(document) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw MaterialFileError(path_.string() + ": " + what);
  }

  const json& parameter(const char* name) const {
    const json& parameters = document_.at("parameters");
    if (!parameters.contains(name)) fail(std::string("no parameter \"") + name + "\"");
    const json& p = parameters.at(name);
    if (!p.is_object() || !p.contains("value"))
      fail(std::string("parameter \"") + name + "\" has no value");
    return p.at("value");
  }

  double number(const json& value, const std::string& name, double low, double high) const {
    if (!value.is_number()) fail("parameter \"" + name + "\" is not a number");
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < low || v > high) {
      std::ostringstream s;
      s << "parameter \"" << name << "\" is " << v << ", outside [" << low << ", " << high
        << "]: not a fitted material";
      fail(s.str());
    }
    return v;
  }

  double scalar(const char* name, double low, double high) const {
    return number(parameter(name), name, low, high);
  }

  Rgb rgb(const char* name, double low, double high) const {
    const json& v = parameter(name);
    if (!v.is_array() || v.size() != 3)
      fail(std::string("parameter \"") + name + "\" is not an RGB triple");
    Rgb out;
    for (std::size_t c = 0; c < 3; ++c) out[c] = number(v[c], name, low, high);
    return out;
  }

 private:
  std::filesystem::path path_;
  const json& document_;
};

// A material file is 6 levels deep (the candidates' parameters' values); nesting far beyond that
// is not one, and is refused while parsing, before any recursion over it.
constexpr int kMaxJsonDepth = 32;

json parseFile(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw MaterialFileError(path.string() + ": is a directory, not a material file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MaterialFileError(path.string() + ": cannot be read (no such file, or no permission)");
  const json::parser_callback_t refuseDeepNesting = [&](int depth, json::parse_event_t event,
                                                        json&) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth)
      throw MaterialFileError(path.string() + ": nested deeper than " +
                              std::to_string(kMaxJsonDepth) + " levels: not a slicecap material");
    return true;
  };
  try {
    return json::parse(in, refuseDeepNesting);
  } catch (const json::parse_error& e) {
    throw MaterialFileError(path.string() + ": not JSON (" + e.what() + ")");
  }
}

fit::FittedMaterial readMaterialDocument(const std::filesystem::path& path, const json& document) {
  const Reader r(path, document);
  if (!document.is_object() || document.value("format", "") != fit::kMaterialFormat)
    r.fail(std::string("not a slicecap material (\"format\" is not \"") + fit::kMaterialFormat +
           "\"): write one with slicecap fit TABLE -o MATERIAL.json");
  // An integer: 1.5 is not version 1 (json::value would have truncated it to 1).
  const json* version = document.contains("format_version") ? &document.at("format_version") : nullptr;
  const long long versionNumber =
      version != nullptr && version->is_number_integer() ? version->get<long long>() : -1;
  if (versionNumber != fit::kMaterialFormatVersion &&
      versionNumber != fit::kMaterialFormatVersionAdditiveSheen)
    r.fail("format_version " + document.value("format_version", json()).dump() +
           " is not one this build reads (" +
           std::to_string(fit::kMaterialFormatVersionAdditiveSheen) + " or " +
           std::to_string(fit::kMaterialFormatVersion) + ")");
  if (!document.contains("parameters") || !document.at("parameters").is_object())
    r.fail("no \"parameters\": not a completed fit");
  // A completed fit always records how close it came; without that the file was not written by a
  // fit that converged (or was edited), and an export would hide that.
  const json* metrics = document.contains("metrics") ? &document.at("metrics") : nullptr;
  if (metrics == nullptr || !metrics->is_object() || !metrics->contains("delta_e") ||
      !metrics->at("delta_e").is_number() || !std::isfinite(metrics->at("delta_e").get<double>()) ||
      metrics->at("delta_e").get<double>() < 0.0)
    r.fail("no finite, non-negative \"metrics\".\"delta_e\": not a completed fit");

  const std::string model = document.value("model", "");
  fit::FittedMaterial m;
  bool known = false;
  for (const fit::MaterialModel candidate :
       {fit::MaterialModel::Ggx, fit::MaterialModel::GgxSheen, fit::MaterialModel::GgxCoat,
        fit::MaterialModel::GgxSheenCoat}) {
    if (model == toString(candidate)) m.model = candidate, known = true;
  }
  if (!known)
    r.fail("unknown model \"" + model +
           "\" (expected \"ggx\", \"ggx+sheen\", \"ggx+coat\" or \"ggx+sheen+coat\")");
  const double inf = HUGE_VAL;
  // Colours above 1 come from a table whose scale is off (raw counts); only near float32's range
  // (3.4e38) does tabulating the material overflow, and every comparison of it read dE 0 between two
  // infinities. A lobe's peak can multiply a colour by 1e6, hence the margin.
  const double maxColour = 1e30;
  m.diffuseAlbedo = r.rgb("diffuse_albedo", 0.0, maxColour);
  m.specularF0 = r.rgb("specular_f0", 0.0, 1.0);
  m.specularF90 = r.scalar("specular_f90", 0.0, 1.0);
  // The fit bounds alphas to [0.002, 2]; anything <= 0 is no GGX lobe at all.
  m.alphaTangent = r.scalar("alpha_tangent", 1e-6, inf);
  m.alphaBitangent = r.scalar("alpha_bitangent", 1e-6, inf);
  m.tangentDeg = r.scalar("tangent_deg", -360.0, 360.0);
  // Version 1 has no "sheen_form": its sheen is the additive one, and is evaluated so. Version 2
  // says the form; a file that does not is refused rather than read in a form it may not hold.
  m.sheenForm = fit::SheenForm::Additive;
  if (versionNumber == fit::kMaterialFormatVersion) {
    const std::string form =
        document.contains("sheen_form") && document.at("sheen_form").is_string()
            ? document.at("sheen_form").get<std::string>()
            : std::string();
    if (form == toString(fit::SheenForm::Khr)) {
      m.sheenForm = fit::SheenForm::Khr;
    } else if (form != toString(fit::SheenForm::Additive)) {
      r.fail("\"sheen_form\" is " + (document.contains("sheen_form") ? document.at("sheen_form").dump()
                                                                   : std::string("missing")) +
             ", not \"" + std::string(toString(fit::SheenForm::Khr)) + "\" or \"" +
             std::string(toString(fit::SheenForm::Additive)) + "\"");
    }
  }
  if (fit::hasSheen(m.model)) {
    // KHR_materials_sheen's colour is at most 1 (the base's scaling 1 - s E stays positive).
    const bool khr = m.sheenForm == fit::SheenForm::Khr;
    m.sheenColour = r.rgb("sheen_colour", 0.0, khr ? 1.0 : maxColour);
    // The khr form's albedo E is tabulated over the fit's own roughness range (sheen_albedo.hpp).
    m.sheenRoughness = r.scalar("sheen_roughness", khr ? fit::kSheenAlbedoMinRoughness : 1e-6, 1.0);
  }
  if (fit::hasCoat(m.model)) {
    m.coatWeight = r.scalar("coat_weight", 0.0, 1.0);
    m.coatAlpha = r.scalar("coat_alpha", 1e-6, inf);
  }
  return m.canonical();
}

}  // namespace

fit::FittedMaterial readFittedMaterial(const std::filesystem::path& path) {
  const json document = parseFile(path);
  try {
    return readMaterialDocument(path, document);
  } catch (const json::exception& e) {
    // A field of the wrong JSON type (a string where a number belongs).
    throw MaterialFileError(path.string() + ": malformed material (" + e.what() + ")");
  }
}

}  // namespace slicecap::material_export
