// The rule for a session's id, shared by the session store (a folder name) and the control
// protocol (a request's field), so the protocol checks ids without linking the capture pipeline.
#pragma once

#include <string>

namespace slicecap {

/// \brief True for 1-64 characters of [a-z0-9_-], the first a letter or digit. Never throws.
bool isValidSessionId(const std::string& id);

}  // namespace slicecap
