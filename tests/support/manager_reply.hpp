// A SessionManager command that must succeed: its JSON reply, or a test failure naming the command
// and the refusal (the session-manager and session-exporter tests drive the manager this way).
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <variant>

#include "slicecap/daemon/session_manager.hpp"

namespace slicecap::test {

inline nlohmann::json ok(daemon::SessionManager& manager, const control::Command& command) {
  auto reply = manager.handle(command);
  if (auto* error = std::get_if<control::ProtocolError>(&reply)) {
    ADD_FAILURE() << control::commandName(command) << " refused: " << error->message;
    return {};
  }
  return std::get<nlohmann::json>(reply);
}

}  // namespace slicecap::test
