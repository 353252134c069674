// JSON field access with errors that name the file and the field.
#include "json_fields.hpp"

#include <cmath>
#include <limits>

#include "slicecap/io/json_numbers.hpp"

namespace slicecap::io::json_fields {

const json& object(const json& value, const Location& at) {
  if (!value.is_object()) at.fail("expected an object");
  return value;
}

const json& member(const json& parent, const std::string& key, const Location& at) {
  object(parent, at);
  const auto it = parent.find(key);
  if (it == parent.end()) (at / key).fail("missing field");
  return *it;
}

const json& array(const json& parent, const std::string& key, const Location& at) {
  const json& value = member(parent, key, at);
  if (!value.is_array()) (at / key).fail("expected an array");
  return value;
}

double number(const json& parent, const std::string& key, const Location& at) {
  const json& value = member(parent, key, at);
  if (!value.is_number()) (at / key).fail("expected a number, got " + value.dump());
  const double v = value.get<double>();
  if (!std::isfinite(v)) (at / key).fail("not finite");
  return v;
}

double positiveNumber(const json& parent, const std::string& key, const Location& at) {
  const double v = number(parent, key, at);
  if (!(v > 0.0))
    (at / key).fail("expected a positive number, got " + member(parent, key, at).dump());
  return v;
}

std::int64_t integer(const json& parent, const std::string& key, const Location& at) {
  const json& value = member(parent, key, at);
  const auto v = wholeNumberIn(value, std::numeric_limits<std::int64_t>::min(),
                               std::numeric_limits<std::int64_t>::max());
  if (!v) (at / key).fail("expected an integer, got " + value.dump());
  return *v;
}

std::string string(const json& parent, const std::string& key, const Location& at) {
  const json& value = member(parent, key, at);
  if (!value.is_string()) (at / key).fail("expected a string, got " + value.dump());
  return value.get<std::string>();
}

bool boolean(const json& parent, const std::string& key, const Location& at) {
  const json& value = member(parent, key, at);
  if (!value.is_boolean()) (at / key).fail("expected true or false, got " + value.dump());
  return value.get<bool>();
}

Rgb rgb(const json& parent, const std::string& key, const Location& at) {
  const json& value = member(parent, key, at);
  if (value.is_number()) return Rgb::gray(number(parent, key, at));
  if (!value.is_array() || value.size() != 3)
    (at / key).fail("expected [r, g, b] or one number, got " + value.dump());
  Rgb out;
  for (std::size_t c = 0; c < 3; ++c) {
    if (!value[c].is_number()) (at / key).fail("expected [r, g, b] numbers, got " + value.dump());
    out[c] = value[c].get<double>();
  }
  return out;
}

vision::RectMm rect(const json& parent, const std::string& key, const Location& at) {
  const json& value = object(member(parent, key, at), at / key);
  const Location here = at / key;
  return {number(value, "x_min_mm", here), number(value, "y_min_mm", here),
          number(value, "x_max_mm", here), number(value, "y_max_mm", here)};
}

json toJson(const vision::RectMm& r) {
  return {{"x_min_mm", r.xMinMm},
          {"y_min_mm", r.yMinMm},
          {"x_max_mm", r.xMaxMm},
          {"y_max_mm", r.yMaxMm}};
}

json toJson(const Rgb& v) {
  return json::array({v[0], v[1], v[2]});
}

}  // namespace slicecap::io::json_fields
