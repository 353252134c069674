// The daemon's Unix socket: clients send request lines, get one response line each.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/daemon/protocol.hpp"

namespace slicecap::daemon {

/// \brief Thrown by a request handler to refuse a request with a code; the server replies with it.
class RequestError : public std::runtime_error {
 public:
  RequestError(ErrorCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

/// \brief Answers one request: returns the result, or throws RequestError (any other exception is
/// answered as `internal`, and the daemon stays up).
using RequestHandler = std::function<nlohmann::json(const Request&)>;

/// \brief Limits that keep one client from starving the others or the camera.
struct ServerLimits {
  std::size_t maxClients = 128;                 ///< further connections are closed at once
  std::size_t maxPendingOutputBytes = 1 << 20;  ///< a client that stops reading is dropped
};

/// \brief Where the socket comes from.
struct ListenSpec {
  std::filesystem::path path;        ///< bound when systemd did not pass a socket
  unsigned mode = 0660;              ///< permissions of a socket the daemon binds itself
  std::optional<std::string> group;  ///< owner group of that socket (e.g. "slicecap")
};

/// \brief Creates the listening socket: the one systemd passed (socket activation) or a fresh bind
/// of `spec.path` (a stale socket file left by a crash is replaced; a live one is an error). Throws
/// std::runtime_error naming the path.
int openListenSocket(const ListenSpec& spec, bool* fromSystemd = nullptr);

/// \brief Serves a listening socket on an event loop: any number of clients, request lines of at
/// most kMaxRequestBytes, one response line each, in order.
class ControlServer {
 public:
  ControlServer(EventLoop& loop, int listenFd, RequestHandler handler, ServerLimits limits = {});
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  std::size_t clientCount() const { return clients_.size(); }

 private:
  struct Client;
  void accept();
  void onClientEvent(int fd, std::uint32_t events);
  void handleLine(Client& client, std::string_view line);
  void flush(int fd);
  void drop(int fd);

  EventLoop& loop_;
  int listenFd_;
  RequestHandler handler_;
  ServerLimits limits_;
  std::map<int, std::unique_ptr<Client>> clients_;
};

}  // namespace slicecap::daemon
