// The daemon's Unix socket: clients send request lines, get one response line each.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/core/error.hpp"
#include "slicecap/daemon/event_loop.hpp"
#include "slicecap/control/protocol.hpp"

namespace slicecap::daemon {

/// \brief Thrown by a request handler to refuse a request with a code; the server replies with it.
class RequestError : public slicecap::Error {
 public:
  RequestError(control::ErrorCode code, const std::string& message)
      : slicecap::Error(message), code_(code) {}
  control::ErrorCode code() const { return code_; }

 private:
  control::ErrorCode code_;
};

/// \brief Answers one request: returns the result, or throws RequestError (any other exception is
/// answered as `internal`, and the daemon stays up).
using RequestHandler = std::function<nlohmann::json(const control::Request&)>;

/// \brief Limits that keep one client from starving the others or the camera.
struct ServerLimits {
  std::size_t maxClients = 128;                 ///< further connections are closed at once
  std::size_t maxPendingOutputBytes = 1 << 20;  ///< a client that stops reading is dropped
  /// A client that sends nothing for this long is closed (zero: never), so idle connections
  /// cannot hold every slot; slicecapd.conf's client_idle_timeout_s.
  std::chrono::milliseconds idleTimeout = std::chrono::seconds(300);
  /// Members of this group may connect, besides root and the daemon's own uid (ListenSocket::group:
  /// the socket file's); empty: nobody else.
  std::optional<std::uint32_t> socketGroup;
};

/// \brief Whether a peer (SO_PEERCRED's uid and gid, SO_PEERGROUPS' supplementary groups) may use
/// the socket: root, the daemon's own uid (`self`), and members of the socket's group.
bool peerMayConnect(const control::Peer& peer, const std::vector<std::uint32_t>& supplementaryGroups,
                    std::optional<std::uint32_t> socketGroup, std::uint32_t self);

/// \brief Where the socket comes from.
struct ListenSpec {
  std::filesystem::path path;        ///< bound when systemd did not pass a socket
  unsigned mode = 0660;              ///< permissions of a socket the daemon binds itself
  std::optional<std::string> group;  ///< owner group of that socket (e.g. "slicecap")
  /// Test seam: called right after bind() with where the socket node was created.
  std::function<void(const std::filesystem::path& bound)> afterBind{};
};

/// \brief Why `path` cannot be the daemon's socket (longer than sun_path holds, with the room the
/// daemon needs to bind it beside the path first), or empty when it can.
std::optional<std::string> socketPathProblem(const std::filesystem::path& path);

/// \brief The listening socket: the one systemd passed (socket activation) or a fresh bind of
/// `spec.path`. A fresh socket is bound in a private folder beside the path, given its mode and
/// group there and then renamed into place, so it is never reachable with wider permissions,
/// whatever the umask (a stale socket file left by a crash is replaced; a live one is an error).
/// Closing it removes the socket file it bound (if it is still there), never systemd's.
class ListenSocket {
 public:
  /// \brief Throws SlicecapdError naming the path.
  explicit ListenSocket(const ListenSpec& spec);
  ~ListenSocket();
  ListenSocket(const ListenSocket&) = delete;
  ListenSocket& operator=(const ListenSocket&) = delete;

  int fd() const { return fd_; }
  bool fromSystemd() const { return fromSystemd_; }
  /// \brief The group of the socket file (who may connect), if it can be found.
  std::optional<std::uint32_t> group() const { return group_; }
  /// \brief Gives up the descriptor: the caller closes it, and the socket file stays.
  int release();

 private:
  int fd_ = -1;
  bool fromSystemd_ = false;
  std::optional<std::uint32_t> group_;
  std::filesystem::path bound_;  // the file to remove on close; empty: none (systemd's socket)
  std::uint64_t device_ = 0, inode_ = 0;
};

/// \brief A ListenSocket's descriptor, for a caller that closes it itself (the socket file stays).
/// Throws SlicecapdError naming the path.
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
  bool admit(int fd, control::Peer& peer);
  void reapHungUp();
  void closeIdle();
  void onClientEvent(int fd, std::uint32_t events);
  void handleLine(Client& client, std::string_view line);
  void flush(int fd);
  void drop(int fd);

  EventLoop& loop_;
  int listenFd_;
  RequestHandler handler_;
  ServerLimits limits_;
  std::map<int, std::unique_ptr<Client>> clients_;
  std::optional<EventLoop::TimerId> idleTimer_;
};

}  // namespace slicecap::daemon
