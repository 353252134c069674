// Typed access to JSON fields whose errors name the file and the field path (io-internal).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "slicecap/core/rgb.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::io::json_fields {

using nlohmann::json;

/// \brief Where a JSON value sits: the file and the path inside it, e.g. "frames[3]".
struct Location {
  std::string file;
  std::string path;
  Location operator/(const std::string& key) const {
    return {file, path.empty() ? key : path + "." + key};
  }
  Location operator[](std::size_t index) const {
    return {file, path + "[" + std::to_string(index) + "]"};
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(file + ": " + (path.empty() ? std::string("top level") : path) + ": " + what);
  }
};

/// \brief The object at `at`, or an error saying it must be one.
const json& object(const json& value, const Location& at);
/// \brief A member that must be present.
const json& member(const json& parent, const std::string& key, const Location& at);
/// \brief The array at parent[key] (present, an array).
const json& array(const json& parent, const std::string& key, const Location& at);

double number(const json& parent, const std::string& key, const Location& at);
double positiveNumber(const json& parent, const std::string& key, const Location& at);
std::int64_t integer(const json& parent, const std::string& key, const Location& at);
std::string string(const json& parent, const std::string& key, const Location& at);
bool boolean(const json& parent, const std::string& key, const Location& at);
/// \brief An albedo: [r, g, b] or one number for all three.
Rgb rgb(const json& parent, const std::string& key, const Location& at);
/// \brief {"x_min_mm", "y_min_mm", "x_max_mm", "y_max_mm"}.
vision::RectMm rect(const json& parent, const std::string& key, const Location& at);
json toJson(const vision::RectMm& rect);
json toJson(const Rgb& value);

}  // namespace slicecap::io::json_fields
