// One request line on a Unix socket from a child process running as another user, for tests of
// who may use the control socket (the test process must be root to change its uid).
#pragma once

#include <grp.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace slicecap::test {

/// \brief Whether this process may run a request as another user.
inline bool canChangeUser() {
  return ::geteuid() == 0;
}

/// \brief Sends `line` (with a newline added) on `socket` as uid `uid`, gid `gid` and the
/// supplementary `groups`, from a forked child, and returns the first line it gets back (without
/// the newline), "connect failed: ..." when it cannot connect, or "" when the server closed the
/// connection without a line. The child does only system calls: the parent may have threads.
inline std::string requestAsUser(const std::filesystem::path& socket, uid_t uid, gid_t gid,
                                 const std::vector<gid_t>& groups, const std::string& line) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (socket.native().size() >= sizeof address.sun_path)
    throw std::runtime_error(socket.string() + ": too long for a socket");
  std::strcpy(address.sun_path, socket.c_str());
  const std::string request = line + "\n";
  int output[2];
  if (::pipe(output) != 0) throw std::runtime_error("pipe");
  const pid_t child = ::fork();
  if (child < 0) throw std::runtime_error("fork");
  if (child == 0) {
    ::close(output[0]);
    const auto say = [&](const char* text, std::size_t length) {
      [[maybe_unused]] const auto n = ::write(output[1], text, length);
    };
    if (::setgroups(groups.size(), groups.data()) != 0 || ::setgid(gid) != 0 ||
        ::setuid(uid) != 0) {
      say("cannot change user", 18);
      ::_exit(1);
    }
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      const char* reason = std::strerror(errno);
      say("connect failed: ", 16);
      say(reason, std::strlen(reason));
      ::_exit(0);
    }
    [[maybe_unused]] const auto sent = ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    static char reply[65536];
    std::size_t length = 0;
    while (length < sizeof reply) {
      const ssize_t n = ::recv(fd, reply + length, sizeof reply - length, 0);
      if (n <= 0) break;
      length += std::size_t(n);
      if (std::memchr(reply, '\n', length)) break;
    }
    say(reply, length);
    ::_exit(0);
  }
  ::close(output[1]);
  std::string reply;
  char chunk[4096];
  for (ssize_t n; (n = ::read(output[0], chunk, sizeof chunk)) > 0;)
    reply.append(chunk, std::size_t(n));
  ::close(output[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  if (const auto newline = reply.find('\n'); newline != std::string::npos) reply.resize(newline);
  return reply;
}

}  // namespace slicecap::test
