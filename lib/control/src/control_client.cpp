// Blocking client with a timeout for the control socket.
#include "slicecap/control/control_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace slicecap::control {

ControlClient::ControlClient(const std::filesystem::path& socketPath,
                             std::chrono::milliseconds timeout)
    : socketPath_(socketPath), timeout_(timeout) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (socketPath.native().size() >= sizeof address.sun_path) {
    throw ConnectionError(socketPath.string() + ": socket path too long");
  }
  std::strcpy(address.sun_path, socketPath.c_str());
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0)
    throw ConnectionError(std::string("cannot create a socket: ") + std::strerror(errno));
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    throw ConnectionError("cannot reach slicecapd at " + socketPath.string() + ": " +
                          std::strerror(error) +
                          (error == ENOENT || error == ECONNREFUSED
                               ? " (is the daemon running? systemctl status slicecapd)"
                               : ""));
  }
}

ControlClient::~ControlClient() {
  if (fd_ >= 0) ::close(fd_);
}

std::string ControlClient::readLine() {
  const auto deadline = std::chrono::steady_clock::now() + timeout_;
  while (true) {
    if (const auto newline = buffer_.find('\n'); newline != std::string::npos) {
      std::string line = buffer_.substr(0, newline);
      buffer_.erase(0, newline + 1);
      return line;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
      throw ConnectionError("slicecapd at " + socketPath_.string() + " did not answer in time");
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, int(left.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    char chunk[8192];
    const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw ConnectionError("slicecapd at " + socketPath_.string() + " closed the connection");
    buffer_.append(chunk, std::size_t(n));
  }
}

nlohmann::json ControlClient::call(const Command& command) {
  const std::int64_t id = nextId_++;
  const std::string line = encodeRequest({id, command}) + "\n";
  for (std::size_t sent = 0; sent < line.size();) {
    const ssize_t n = ::send(fd_, line.data() + sent, line.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw ConnectionError("cannot send to slicecapd at " + socketPath_.string() + ": " +
                            std::strerror(errno));
    sent += std::size_t(n);
  }
  const nlohmann::json response = nlohmann::json::parse(readLine(), nullptr, false);
  if (response.is_discarded() || !response.is_object() || !response.contains("ok")) {
    throw ConnectionError("slicecapd at " + socketPath_.string() + " sent a malformed answer");
  }
  // A request the daemon could not read (e.g. over kMaxRequestBytes) is answered without its id.
  if (response["ok"] == false && response.value("id", nlohmann::json()).is_null()) {
    const nlohmann::json& error = response.value("error", nlohmann::json::object());
    throw DaemonError(error.value("code", "internal"), error.value("message", "no message"));
  }
  if (response.value("id", nlohmann::json()) != id)
    throw ConnectionError("slicecapd answered another request");
  if (response["ok"] == true) return response.value("result", nlohmann::json::object());
  const nlohmann::json& error = response.value("error", nlohmann::json::object());
  throw DaemonError(error.value("code", "internal"), error.value("message", "no message"));
}

}  // namespace slicecap::control
