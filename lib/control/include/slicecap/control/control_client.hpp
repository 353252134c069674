// The client side of the control socket, used by the `slicecap` command.
#pragma once

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "slicecap/control/protocol.hpp"
#include "slicecap/core/error.hpp"

namespace slicecap::control {

/// \brief The daemon could not be reached or answered nonsense; the message says which and names
/// the socket.
class ConnectionError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief The daemon refused a request; code() is the protocol's error code.
class DaemonError : public slicecap::Error {
 public:
  DaemonError(std::string code, const std::string& message)
      : slicecap::Error(message), code_(std::move(code)) {}
  const std::string& code() const { return code_; }

 private:
  std::string code_;
};

/// \brief One connection to slicecapd; requests are answered in order.
class ControlClient {
 public:
  /// \brief Connects; ConnectionError naming the socket (and saying whether it is missing or
  /// refused).
  explicit ControlClient(const std::filesystem::path& socketPath,
                         std::chrono::milliseconds timeout = std::chrono::seconds(30));
  ~ControlClient();
  ControlClient(const ControlClient&) = delete;
  ControlClient& operator=(const ControlClient&) = delete;

  /// \brief Sends a command and waits for its answer: the result, or DaemonError for a refusal, or
  /// ConnectionError when the connection fails or times out.
  nlohmann::json call(const Command& command);

 private:
  std::string readLine();
  std::filesystem::path socketPath_;
  std::chrono::milliseconds timeout_;
  int fd_ = -1;
  std::int64_t nextId_ = 1;
  std::string buffer_;
};

}  // namespace slicecap::control
