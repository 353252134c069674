#include "slicecap/core/session_id.hpp"

#include <algorithm>

namespace slicecap {

bool isValidSessionId(const std::string& id) {
  auto letterOrDigit = [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); };
  // Not starting with '-' or '_': an id is an argument of the CLI, where "-x" reads as an option;
  // no '.' or '/': it names a folder under the storage root.
  return !id.empty() && id.size() <= 64 && letterOrDigit(id.front()) &&
         std::all_of(id.begin(), id.end(),
                     [&](char c) { return letterOrDigit(c) || c == '_' || c == '-'; });
}

}  // namespace slicecap
