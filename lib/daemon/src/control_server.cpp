// The control socket: accept, per-client line buffers, ordered responses, limits.
#include "slicecap/daemon/control_server.hpp"

#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <utility>

namespace slicecap::daemon {

struct ControlServer::Client {
  std::string input;
  std::string output;
  bool discardingOversizedLine = false;
  control::Peer peer;
  std::chrono::steady_clock::time_point lastHeard = std::chrono::steady_clock::now();
};

bool peerMayConnect(const control::Peer& peer, const std::vector<std::uint32_t>& supplementaryGroups,
                    std::optional<std::uint32_t> socketGroup, std::uint32_t self) {
  if (peer.uid == 0 || peer.uid == self) return true;
  if (!socketGroup) return false;
  return peer.gid == *socketGroup ||
         std::find(supplementaryGroups.begin(), supplementaryGroups.end(), *socketGroup) !=
             supplementaryGroups.end();
}

ControlServer::ControlServer(EventLoop& loop, int listenFd, RequestHandler handler,
                             ServerLimits limits)
    : loop_(loop), listenFd_(listenFd), handler_(std::move(handler)), limits_(limits) {
  loop_.watch(listenFd_, EPOLLIN, [this](std::uint32_t) { accept(); });
  if (limits_.idleTimeout.count() > 0) {
    // Checked at a quarter of the timeout: an idle client goes after 1 to 1.25 timeouts.
    idleTimer_ = loop_.addTimer(std::max(limits_.idleTimeout / 4, std::chrono::milliseconds(1)),
                                true, [this] { closeIdle(); });
  }
}

ControlServer::~ControlServer() {
  for (const auto& [fd, client] : clients_) {
    loop_.unwatch(fd);
    ::close(fd);
  }
  if (idleTimer_) loop_.cancelTimer(*idleTimer_);
  loop_.unwatch(listenFd_);
}

namespace {

void sayAndClose(int fd, control::ErrorCode code, const std::string& message) {
  const std::string line = control::encodeError({code, message, std::nullopt}) + "\n";
  [[maybe_unused]] const auto n = ::send(fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  ::close(fd);
}

std::vector<std::uint32_t> supplementaryGroups(int fd) {
  std::vector<gid_t> groups(64);
  socklen_t length = socklen_t(groups.size() * sizeof(gid_t));
  if (::getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups.data(), &length) != 0) {
    if (errno != ERANGE) return {};
    groups.resize(length / sizeof(gid_t));
    if (::getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups.data(), &length) != 0) return {};
  }
  groups.resize(length / sizeof(gid_t));
  return {groups.begin(), groups.end()};
}

}  // namespace

// Who connected: the peer's credentials, checked against the socket's group. The file mode keeps
// others out, but a client that connected while it was wider (or through a mode set by hand)
// would otherwise stay.
bool ControlServer::admit(int fd, control::Peer& peer) {
  ucred credentials{};
  socklen_t length = sizeof credentials;
  if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &credentials, &length) != 0) {
    sayAndClose(fd, control::ErrorCode::PermissionDenied, "cannot tell who is connecting");
    return false;
  }
  peer = {credentials.pid, credentials.uid, credentials.gid};
  if (peerMayConnect(peer, supplementaryGroups(fd), limits_.socketGroup, ::geteuid())) return true;
  sayAndClose(fd, control::ErrorCode::PermissionDenied,
              "uid " + std::to_string(peer.uid) + " is not in the socket's group" +
                  (limits_.socketGroup ? " (gid " + std::to_string(*limits_.socketGroup) + ")"
                                       : std::string()));
  return false;
}

void ControlServer::accept() {
  while (true) {
    const int fd = ::accept4(listenFd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN: all accepted; other errors: try again on the next event
    control::Peer peer;
    if (!admit(fd, peer)) continue;
    // Clients that hung up but whose hang-up the loop has not read yet (one read a wake-up) hold
    // no slot.
    if (clients_.size() >= limits_.maxClients) reapHungUp();
    if (clients_.size() >= limits_.maxClients) {
      sayAndClose(fd, control::ErrorCode::Unavailable,
                  "too many clients (" + std::to_string(limits_.maxClients) + ")");
      continue;
    }
    auto client = std::make_unique<Client>();
    client->peer = peer;
    clients_[fd] = std::move(client);
    loop_.watch(fd, EPOLLIN | EPOLLRDHUP,
                [this, fd](std::uint32_t events) { onClientEvent(fd, events); });
  }
}

void ControlServer::reapHungUp() {
  std::vector<pollfd> polled;
  polled.reserve(clients_.size());
  for (const auto& [fd, client] : clients_)
    polled.push_back({fd, POLLRDHUP, 0});
  if (::poll(polled.data(), nfds_t(polled.size()), 0) <= 0) return;
  for (const pollfd& p : polled) {
    if (!(p.revents & (POLLRDHUP | POLLHUP | POLLERR | POLLNVAL))) continue;
    // What it sent before hanging up is still answered (as far as it can be), as on its own
    // wake-up; once its input is read, the hang-up drops it.
    for (int round = 0; round < 1024 && clients_.count(p.fd); ++round)
      onClientEvent(p.fd, EPOLLIN | EPOLLRDHUP);
    if (clients_.count(p.fd)) drop(p.fd);
  }
}

void ControlServer::closeIdle() {
  const auto now = std::chrono::steady_clock::now();
  std::vector<int> idle;
  for (const auto& [fd, client] : clients_)
    if (now - client->lastHeard >= limits_.idleTimeout) idle.push_back(fd);
  for (const int fd : idle) {
    loop_.unwatch(fd);
    clients_.erase(fd);
    const auto ms = limits_.idleTimeout.count();
    sayAndClose(
        fd, control::ErrorCode::Unavailable,
        "connection closed after " +
            (ms % 1000 == 0 ? std::to_string(ms / 1000) + " s" : std::to_string(ms) + " ms") +
            " without a request (client_idle_timeout_s)");
  }
}

void ControlServer::onClientEvent(int fd, std::uint32_t events) {
  auto it = clients_.find(fd);
  if (it == clients_.end()) return;
  Client& client = *it->second;
  if (events & EPOLLOUT) flush(fd);
  if (!clients_.count(fd)) return;
  if (events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR)) {
    char buffer[16384];
    while (true) {
      const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
      if (n > 0) {
        client.lastHeard = std::chrono::steady_clock::now();
        client.input.append(buffer, std::size_t(n));
        std::size_t start = 0;
        for (std::size_t newline; (newline = client.input.find('\n', start)) != std::string::npos;
             start = newline + 1) {
          if (client.discardingOversizedLine) {
            client.discardingOversizedLine = false;  // the rest of the oversized line ends here
            continue;
          }
          handleLine(client, std::string_view(client.input).substr(start, newline - start));
        }
        client.input.erase(0, start);
        if (client.input.size() > control::kMaxRequestBytes) {
          // Answer now and drop the line's remainder as it arrives: memory stays bounded.
          if (!client.discardingOversizedLine) {
            client.output +=
                control::encodeError({control::ErrorCode::TooLarge,
                             "request longer than " + std::to_string(control::kMaxRequestBytes) + " bytes",
                             std::nullopt}) +
                "\n";
          }
          client.discardingOversizedLine = true;
          client.input.clear();
        }
        // One read a wake-up: epoll is level-triggered, so the rest comes on the next round,
        // after the other clients, the camera's frames and the watchdog have had theirs. Reading
        // until EAGAIN let a client that writes without pause hold the loop (its unread answers
        // piling up) until the watchdog killed the daemon; now flush() drops it once those pass
        // maxPendingOutputBytes.
        break;
      }
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
      if (n < 0 && errno == EINTR) continue;
      flush(fd);  // answer what was asked before the client hung up
      drop(fd);
      return;
    }
    flush(fd);
  }
}

void ControlServer::handleLine(Client& client, std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  auto parsed = control::parseRequest(line);
  if (auto* error = std::get_if<control::ProtocolError>(&parsed)) {
    client.output += control::encodeError(*error) + "\n";
    return;
  }
  control::Request& request = std::get<control::Request>(parsed);
  request.peer = client.peer;
  try {
    client.output += control::encodeResult(request.id, handler_(request)) + "\n";
  } catch (const RequestError& e) {
    client.output += control::encodeError({e.code(), e.what(), request.id}) + "\n";
  } catch (const std::exception& e) {
    client.output += control::encodeError({control::ErrorCode::Internal, e.what(), request.id}) + "\n";
  }
}

void ControlServer::flush(int fd) {
  auto it = clients_.find(fd);
  if (it == clients_.end()) return;
  Client& client = *it->second;
  while (!client.output.empty()) {
    const ssize_t n = ::send(fd, client.output.data(), client.output.size(), MSG_NOSIGNAL);
    if (n > 0) {
      client.output.erase(0, std::size_t(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    drop(fd);
    return;
  }
  if (client.output.size() > limits_.maxPendingOutputBytes) {
    drop(fd);  // it stopped reading its answers
    return;
  }
  loop_.modify(fd, EPOLLIN | EPOLLRDHUP | (client.output.empty() ? 0u : std::uint32_t(EPOLLOUT)));
}

void ControlServer::drop(int fd) {
  // Once only: a client that hangs up with answers unsent is dropped by flush(), and then again by
  // its hang-up; the second close() could shut a descriptor another thread (the frame recorder's
  // writer, libcamera's) had been given the same number in between.
  if (!clients_.count(fd)) return;
  loop_.unwatch(fd);
  ::close(fd);
  clients_.erase(fd);
}

}  // namespace slicecap::daemon
