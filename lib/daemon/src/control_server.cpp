// The control socket: accept, per-client line buffers, ordered responses, limits.
#include "slicecap/daemon/control_server.hpp"

#include <fcntl.h>
#include <grp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <systemd/sd-daemon.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace slicecap::daemon {
namespace {

std::runtime_error socketError(const std::filesystem::path& path, const std::string& what) {
  return std::runtime_error(path.string() + ": " + what + ": " + std::strerror(errno));
}

sockaddr_un socketAddress(const std::filesystem::path& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.native().size() >= sizeof address.sun_path) {
    throw std::runtime_error(path.string() + ": socket path longer than " +
                             std::to_string(sizeof address.sun_path - 1) + " bytes");
  }
  std::strcpy(address.sun_path, path.c_str());
  return address;
}

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
};

int openListenSocket(const ListenSpec& spec, bool* fromSystemd) {
  if (sd_listen_fds(0) == 1) {
    if (fromSystemd) *fromSystemd = true;
    const int fd = SD_LISTEN_FDS_START;
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    return fd;
  }
  if (fromSystemd) *fromSystemd = false;
  const sockaddr_un address = socketAddress(spec.path);
  struct stat existing {};
  if (::lstat(spec.path.c_str(), &existing) == 0) {
    if (!S_ISSOCK(existing.st_mode))
      throw std::runtime_error(spec.path.string() + ": exists and is not a socket");
    if (socketIsLive(address))
      throw std::runtime_error(spec.path.string() + ": another daemon is listening there");
    ::unlink(spec.path.c_str());
  }
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw socketError(spec.path, "cannot create socket");
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(fd, 64) != 0) {
    const auto error = socketError(spec.path, "cannot listen");
    ::close(fd);
    throw error;
  }
  // The group may talk to the daemon; nobody else (the socket is the whole control surface).
  if (::chmod(spec.path.c_str(), spec.mode) != 0) {
    const auto error = socketError(spec.path, "cannot set permissions");
    ::close(fd);
    throw error;
  }
  if (spec.group) {
    const group* g = ::getgrnam(spec.group->c_str());
    if (!g || ::chown(spec.path.c_str(), uid_t(-1), g->gr_gid) != 0) {
      ::close(fd);
      throw std::runtime_error(spec.path.string() + ": cannot give the socket to group " +
                               *spec.group);
    }
  }
  return fd;
}

ControlServer::ControlServer(EventLoop& loop, int listenFd, RequestHandler handler,
                             ServerLimits limits)
    : loop_(loop), listenFd_(listenFd), handler_(std::move(handler)), limits_(limits) {
  loop_.watch(listenFd_, EPOLLIN, [this](std::uint32_t) { accept(); });
}

ControlServer::~ControlServer() {
  for (const auto& [fd, client] : clients_) {
    loop_.unwatch(fd);
    ::close(fd);
  }
  loop_.unwatch(listenFd_);
}

void ControlServer::accept() {
  while (true) {
    const int fd = ::accept4(listenFd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN: all accepted; other errors: try again on the next event
    if (clients_.size() >= limits_.maxClients) {
      const std::string busy =
          encodeError({ErrorCode::Unavailable, "too many clients", std::nullopt}) + "\n";
      [[maybe_unused]] const auto n = ::send(fd, busy.data(), busy.size(), MSG_NOSIGNAL);
      ::close(fd);
      continue;
    }
    clients_[fd] = std::make_unique<Client>();
    loop_.watch(fd, EPOLLIN | EPOLLRDHUP,
                [this, fd](std::uint32_t events) { onClientEvent(fd, events); });
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
  const Request& request = std::get<Request>(parsed);
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
