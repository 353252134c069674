// The control socket: accept, per-client line buffers, ordered responses, limits.
#include "slicecap/daemon/control_server.hpp"

#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include "sd_daemon.hpp"
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <utility>

namespace slicecap::daemon {
namespace {

std::runtime_error socketError(const std::filesystem::path& path, const std::string& what) {
  return std::runtime_error(path.string() + ": " + what + ": " + std::strerror(errno));
}

sockaddr_un socketAddress(const std::filesystem::path& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.native().size() >= sizeof address.sun_path)
    throw std::runtime_error(path.string() + ": socket path longer than " +
                             std::to_string(sizeof address.sun_path - 1) + " bytes");
  std::strcpy(address.sun_path, path.c_str());
  return address;
}

// How much longer than its folder's path the socket's first, private path is: "/.sXXXXXX/s".
constexpr std::string_view kPrivateBindSuffix = "/.sXXXXXX/s";

// True when something is listening on the socket file (another daemon): never steal it.
bool socketIsLive(const sockaddr_un& address) {
  const int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (probe < 0) return false;
  const bool live =
      ::connect(probe, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  ::close(probe);
  return live;
}

}  // namespace

struct ControlServer::Client {
  std::string input;
  std::string output;
  bool discardingOversizedLine = false;
  Peer peer;
  std::chrono::steady_clock::time_point lastHeard = std::chrono::steady_clock::now();
};

std::optional<std::string> socketPathProblem(const std::filesystem::path& path) {
  constexpr std::size_t kMax = sizeof(sockaddr_un::sun_path) - 1;
  if (path.native().size() > kMax)
    return path.string() + ": socket path longer than " + std::to_string(kMax) + " bytes";
  // The socket is first bound as <folder>/.sXXXXXX/s (see ListenSocket).
  if (path.parent_path().native().size() + kPrivateBindSuffix.size() > kMax)
    return path.string() + ": the socket's folder path is longer than " +
           std::to_string(kMax - kPrivateBindSuffix.size()) +
           " bytes (the daemon binds the socket in a private folder there first)";
  return std::nullopt;
}

bool peerMayConnect(const Peer& peer, const std::vector<std::uint32_t>& supplementaryGroups,
                    std::optional<std::uint32_t> socketGroup, std::uint32_t self) {
  if (peer.uid == 0 || peer.uid == self) return true;
  if (!socketGroup) return false;
  return peer.gid == *socketGroup ||
         std::find(supplementaryGroups.begin(), supplementaryGroups.end(), *socketGroup) !=
             supplementaryGroups.end();
}

namespace {

// The group of the socket file systemd passed as `fd`, if it can be found.
std::optional<std::uint32_t> passedSocketGroup(int fd) {
  sockaddr_un address{};
  socklen_t length = sizeof address;
  struct stat file {};
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0 &&
      length > offsetof(sockaddr_un, sun_path) && address.sun_path[0] != '\0' &&
      ::stat(address.sun_path, &file) == 0)
    return file.st_gid;
  return std::nullopt;
}

// Throws naming `path` when something other than a stale socket is there.
void refuseOccupiedPath(const std::filesystem::path& path) {
  const sockaddr_un address = socketAddress(path);
  struct stat existing {};
  if (::lstat(path.c_str(), &existing) == 0) {
    if (!S_ISSOCK(existing.st_mode))
      throw std::runtime_error(path.string() + ": exists and is not a socket");
    if (socketIsLive(address))
      throw std::runtime_error(path.string() + ": another daemon is listening there");
    // A stale one: the rename below replaces it.
  }
}

// A listening socket bound as `bound` in `privateFolder`, given the mode and group of `spec`
// there, then renamed to `spec.path`; on failure the descriptor, the node and the folder are
// removed and std::runtime_error names the path.
int listenFromPrivateFolder(const ListenSpec& spec, const std::string& privateFolder,
                            const std::filesystem::path& bound) {
  int fd = -1;
  const auto fail = [&](std::runtime_error error) {
    if (fd >= 0) ::close(fd);
    fd = -1;
    ::unlink(bound.c_str());
    ::rmdir(privateFolder.c_str());
    return error;
  };
  fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw fail(socketError(spec.path, "cannot create socket"));
  const sockaddr_un privateAddress = socketAddress(bound);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&privateAddress), sizeof privateAddress) != 0)
    throw fail(socketError(spec.path, "cannot bind"));
  if (spec.afterBind) spec.afterBind(bound);
  // The group may talk to the daemon; nobody else (the socket is the whole control surface).
  if (::chmod(bound.c_str(), spec.mode) != 0)
    throw fail(socketError(spec.path, "cannot set permissions"));
  if (spec.group) {
    const struct group* g = ::getgrnam(spec.group->c_str());
    if (!g)
      throw fail(std::runtime_error(spec.path.string() + ": socket_group " + *spec.group +
                                    " does not exist"));
    if (::chown(bound.c_str(), uid_t(-1), g->gr_gid) != 0)
      throw fail(socketError(spec.path, "cannot give the socket to group " + *spec.group));
  }
  if (::listen(fd, 64) != 0) throw fail(socketError(spec.path, "cannot listen"));
  if (::rename(bound.c_str(), spec.path.c_str()) != 0)
    throw fail(socketError(spec.path, "cannot move the socket into place"));
  return fd;
}

}  // namespace

ListenSocket::ListenSocket(const ListenSpec& spec) {
  if (sd_listen_fds(0) == 1) {
    fromSystemd_ = true;
    fd_ = SD_LISTEN_FDS_START;
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
    // Its group (SocketGroup=) says who may connect; the file is systemd's to remove.
    group_ = passedSocketGroup(fd_);
    return;
  }
  if (const auto problem = socketPathProblem(spec.path)) throw std::runtime_error(*problem);
  refuseOccupiedPath(spec.path);
  // Bound where only this uid can reach it (mkdtemp makes a 0700 folder, whatever the umask), given
  // its mode and group there, then renamed into place: a chmod after binding at the path itself
  // left a window in which, with a permissive umask, anybody could connect (and stay connected).
  // The umask is not changed: it is the whole process's, and other threads may be creating files.
  std::string privateFolder =
      (spec.path.parent_path() / kPrivateBindSuffix.substr(1, kPrivateBindSuffix.size() - 3))
          .string();
  if (!::mkdtemp(privateFolder.data()))
    throw socketError(spec.path, "cannot make a private folder beside it");
  const std::filesystem::path bound = std::filesystem::path(privateFolder) / "s";
  fd_ = listenFromPrivateFolder(spec, privateFolder, bound);
  ::rmdir(privateFolder.c_str());
  struct stat placed {};
  if (::lstat(spec.path.c_str(), &placed) == 0) {
    bound_ = spec.path;
    device_ = placed.st_dev;
    inode_ = placed.st_ino;
    group_ = placed.st_gid;
  }
}

ListenSocket::~ListenSocket() {
  // Only the file this socket made, and only if it is still that one: a second daemon that
  // replaced a stale socket owns the path now.
  struct stat placed {};
  if (!bound_.empty() && ::lstat(bound_.c_str(), &placed) == 0 &&
      std::uint64_t(placed.st_dev) == device_ && std::uint64_t(placed.st_ino) == inode_)
    ::unlink(bound_.c_str());
  if (fd_ >= 0) ::close(fd_);
}

int ListenSocket::release() {
  bound_.clear();
  return std::exchange(fd_, -1);
}

int openListenSocket(const ListenSpec& spec, bool* fromSystemd) {
  ListenSocket socket(spec);
  if (fromSystemd) *fromSystemd = socket.fromSystemd();
  return socket.release();
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

void sayAndClose(int fd, ErrorCode code, const std::string& message) {
  const std::string line = encodeError({code, message, std::nullopt}) + "\n";
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
bool ControlServer::admit(int fd, Peer& peer) {
  ucred credentials{};
  socklen_t length = sizeof credentials;
  if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &credentials, &length) != 0) {
    sayAndClose(fd, ErrorCode::PermissionDenied, "cannot tell who is connecting");
    return false;
  }
  peer = {credentials.pid, credentials.uid, credentials.gid};
  if (peerMayConnect(peer, supplementaryGroups(fd), limits_.socketGroup, ::geteuid())) return true;
  sayAndClose(fd, ErrorCode::PermissionDenied,
              "uid " + std::to_string(peer.uid) + " is not in the socket's group" +
                  (limits_.socketGroup ? " (gid " + std::to_string(*limits_.socketGroup) + ")"
                                       : std::string()));
  return false;
}

void ControlServer::accept() {
  while (true) {
    const int fd = ::accept4(listenFd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN: all accepted; other errors: try again on the next event
    Peer peer;
    if (!admit(fd, peer)) continue;
    // Clients that hung up but whose hang-up the loop has not read yet (one read a wake-up) hold
    // no slot.
    if (clients_.size() >= limits_.maxClients) reapHungUp();
    if (clients_.size() >= limits_.maxClients) {
      sayAndClose(fd, ErrorCode::Unavailable,
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
        fd, ErrorCode::Unavailable,
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
        if (client.input.size() > kMaxRequestBytes) {
          // Answer now and drop the line's remainder as it arrives: memory stays bounded.
          if (!client.discardingOversizedLine) {
            client.output +=
                encodeError({ErrorCode::TooLarge,
                             "request longer than " + std::to_string(kMaxRequestBytes) + " bytes",
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
  auto parsed = parseRequest(line);
  if (auto* error = std::get_if<ProtocolError>(&parsed)) {
    client.output += encodeError(*error) + "\n";
    return;
  }
  Request& request = std::get<Request>(parsed);
  request.peer = client.peer;
  try {
    client.output += encodeResult(request.id, handler_(request)) + "\n";
  } catch (const RequestError& e) {
    client.output += encodeError({e.code(), e.what(), request.id}) + "\n";
  } catch (const std::exception& e) {
    client.output += encodeError({ErrorCode::Internal, e.what(), request.id}) + "\n";
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
