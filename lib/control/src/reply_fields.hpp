// Reading a reply's fields: the one rule for a missing or mistyped key (ReplyError naming it).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "slicecap/control/reply_views.hpp"

namespace slicecap::control::reply_fields {

using nlohmann::json;

// The field `key` of `object` as T; ReplyError naming the field when it is missing or mistyped.
template <typename T>
T field(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key))
    throw ReplyError("slicecapd's reply has no \"" + std::string(key) + "\"");
  try {
    return object.at(key).get<T>();
  } catch (const json::exception&) {
    throw ReplyError("slicecapd's reply has an unreadable \"" + std::string(key) +
                     "\": " + object.at(key).dump());
  }
}

// The field if it is there and not null.
template <typename T>
std::optional<T> optionalField(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || object.at(key).is_null())
    return std::nullopt;
  return field<T>(object, key);
}

}  // namespace slicecap::control::reply_fields
