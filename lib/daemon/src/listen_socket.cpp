// The daemon's listening socket: systemd's (socket activation), or a fresh one bound in a
// private folder beside the configured path and renamed into place.
#include "slicecap/daemon/control_server.hpp"

#include <fcntl.h>
#include <grp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include "sd_daemon.hpp"
#include "slicecap/daemon/slicecapd_error.hpp"
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <utility>

namespace slicecap::daemon {
namespace {

SlicecapdError socketError(const std::filesystem::path& path, const std::string& what) {
  return SlicecapdError(path.string() + ": " + what + ": " + std::strerror(errno));
}

sockaddr_un socketAddress(const std::filesystem::path& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.native().size() >= sizeof address.sun_path)
    throw SlicecapdError(path.string() + ": socket path longer than " +
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
      throw SlicecapdError(path.string() + ": exists and is not a socket");
    if (socketIsLive(address))
      throw SlicecapdError(path.string() + ": another daemon is listening there");
    // A stale one: the rename below replaces it.
  }
}

// A listening socket bound as `bound` in `privateFolder`, given the mode and group of `spec`
// there, then renamed to `spec.path`; on failure the descriptor, the node and the folder are
// removed and SlicecapdError names the path.
int listenFromPrivateFolder(const ListenSpec& spec, const std::string& privateFolder,
                            const std::filesystem::path& bound) {
  int fd = -1;
  const auto fail = [&](SlicecapdError error) {
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
      throw fail(SlicecapdError(spec.path.string() + ": socket_group " + *spec.group +
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

ListenSocket::ListenSocket(const ListenSpec& spec) {
  if (sd_listen_fds(0) == 1) {
    fromSystemd_ = true;
    fd_ = SD_LISTEN_FDS_START;
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
    // Its group (SocketGroup=) says who may connect; the file is systemd's to remove.
    group_ = passedSocketGroup(fd_);
    return;
  }
  if (const auto problem = socketPathProblem(spec.path)) throw SlicecapdError(*problem);
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

}  // namespace slicecap::daemon
