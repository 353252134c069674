// Material specifications: names, tables, and analytic models with parameters.
#include "slicecap/sim/material.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include "slicecap/core/grid_interpolation.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/sim/patterned_material.hpp"

namespace slicecap::sim {
namespace {

class TableMaterial final : public models::ReflectanceModel {
 public:
  TableMaterial(Abrdf table, std::string name) : table_(std::move(table)), name_(std::move(name)) {}
  Rgb evaluate(const UnitVector& toLight, const UnitVector& toView) const override {
    return slicecap::evaluate(table_, toDirection(toLight), toDirection(toView));
  }
  std::string describe() const override { return "table " + name_; }
  bool isIsotropic() const override { return false; }

 private:
  Abrdf table_;
  std::string name_;
};

// "key=v,v,v,key=v" -> key -> numbers (a key's values run until the next "key=").
std::map<std::string, std::vector<double>> parseParameters(const std::string& spec,
                                                           const std::string& text) {
  std::map<std::string, std::vector<double>> parameters;
  std::string key;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    if (const auto eq = item.find('='); eq != std::string::npos) {
      key = item.substr(0, eq);
      if (parameters.count(key))
        throw MaterialError(spec + ": parameter '" + key + "' given twice");
      parameters[key];
      item = item.substr(eq + 1);
    }
    if (key.empty()) throw MaterialError(spec + ": expected name=value, got '" + item + "'");
    double value = 0.0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (ec != std::errc() || end != item.data() + item.size() || !std::isfinite(value))
      throw MaterialError(spec + ": parameter '" + key + "': '" + item + "' is not a number");
    parameters[key].push_back(value);
  }
  return parameters;
}

class Parameters {
 public:
  Parameters(std::string spec, const std::string& text)
      : spec_(std::move(spec)), values_(parseParameters(spec_, text)) {}
  Rgb colour(const std::string& key, double fallback) {
    const std::vector<double> v = take(key, {fallback});
    if (v.size() == 1) return Rgb::gray(check(key, v[0], 0.0, 1.0));
    if (v.size() != 3)
      throw MaterialError(spec_ + ": parameter '" + key + "' needs 1 or 3 numbers");
    return {check(key, v[0], 0.0, 1.0), check(key, v[1], 0.0, 1.0), check(key, v[2], 0.0, 1.0)};
  }
  double scalar(const std::string& key, double fallback, double lo, double hi) {
    const std::vector<double> v = take(key, {fallback});
    if (v.size() != 1) throw MaterialError(spec_ + ": parameter '" + key + "' takes one number");
    return check(key, v[0], lo, hi);
  }
  void finish() const {
    if (!values_.empty())
      throw MaterialError(spec_ + ": unknown parameter '" + values_.begin()->first + "'");
  }

 private:
  std::vector<double> take(const std::string& key, std::vector<double> fallback) {
    const auto it = values_.find(key);
    if (it == values_.end()) return fallback;
    std::vector<double> v = it->second;
    values_.erase(it);
    return v;
  }
  double check(const std::string& key, double v, double lo, double hi) const {
    if (v < lo || v > hi)
      throw MaterialError(spec_ + ": parameter '" + key + "' must be in [" + std::to_string(lo) +
                          ", " + std::to_string(hi) + "]");
    return v;
  }
  std::string spec_;
  std::map<std::string, std::vector<double>> values_;
};

}  // namespace

std::shared_ptr<const models::ReflectanceModel> makeTableMaterial(Abrdf table, std::string name) {
  return std::make_shared<TableMaterial>(std::move(table), std::move(name));
}

std::shared_ptr<const models::ReflectanceModel> loadMaterial(const std::string& spec) {
  if (auto builtIn = models::findMaterial(spec)) return builtIn;
  const std::filesystem::path path(spec);
  if (path.extension() == ".exr" || path.extension() == ".f32")
    return makeTableMaterial(io::readTable(path), path.filename().string());
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  Parameters p(spec, colon == std::string::npos ? "" : spec.substr(colon + 1));
  std::shared_ptr<const models::ReflectanceModel> model;
  if (kind == "lambert") {
    model = models::makeLambert(p.colour("albedo", 0.5));
  } else if (kind == "ward") {
    const Rgb diffuse = p.colour("diffuse", 0.2), specular = p.colour("specular", 0.1);
    const double ax = p.scalar("ax", 0.1, 0.01, 1.0), ay = p.scalar("ay", 0.3, 0.01, 1.0);
    model = models::makeWard(diffuse, specular, ax, ay, p.scalar("tangent", 0.0, -360.0, 360.0));
  } else if (kind == "ggx") {
    const Rgb diffuse = p.colour("diffuse", 0.05), f0 = p.colour("f0", 0.9);
    const double ax = p.scalar("ax", 0.1, 0.01, 1.0), ay = p.scalar("ay", 0.3, 0.01, 1.0);
    model =
        models::makeAnisotropicGgx(diffuse, f0, ax, ay, p.scalar("tangent", 0.0, -360.0, 360.0));
  } else if (kind == "woven") {
    const double cellMm = p.scalar("cell", 10.0, 0.5, 100.0);
    // fine=1: the threads finer than a pixel, the weave's plain counterpart (a flag: 0 or 1).
    const double fine = p.scalar("fine", 0.0, 0.0, 1.0);
    if (fine != 0.0 && fine != 1.0)
      throw MaterialError(spec + ": parameter 'fine' is 0 or 1, not " + std::to_string(fine));
    model = makeWovenMaterial(cellMm, fine == 1.0);
  } else {
    throw MaterialError("unknown material '" + spec +
                        "': not a built-in name (slicecap generate --list), a .exr/.f32 table, or "
                        "lambert:/ward:/ggx:/woven with parameters");
  }
  p.finish();
  return model;
}

}  // namespace slicecap::sim
