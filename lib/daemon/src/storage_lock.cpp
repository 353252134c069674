// The storage folder's lock: one slicecapd per folder (flock on <root>/.lock).
#include "storage_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "slicecap/io/io_error.hpp"

namespace slicecap::daemon {

StorageLock::StorageLock(const std::filesystem::path& root) {
  // The folder first: a new rig's storage does not exist until its first daemon starts.
  std::error_code error;
  std::filesystem::create_directories(root, error);
  if (error || !std::filesystem::is_directory(root))
    throw io::IoError(root.string() + ": cannot use as session storage: " +
                      (error ? error.message() : "not a folder"));
  const std::filesystem::path lockFile = root / ".lock";
  fd_ = ::open(lockFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw io::IoError(lockFile.string() + ": cannot open: " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int lockError = errno;
    std::string holder;
    char pid[32] = {};
    if (::pread(fd_, pid, sizeof pid - 1, 0) > 0) holder = std::string(pid);
    holder.erase(holder.find_last_not_of(" \n") + 1);
    ::close(fd_);
    fd_ = -1;
    if (lockError == EWOULDBLOCK)
      throw io::IoError(root.string() + ": in use by another slicecapd" +
                        (holder.empty() ? std::string() : " (pid " + holder + ")") +
                        "; one daemon per storage folder");
    throw io::IoError(lockFile.string() + ": cannot lock: " + std::strerror(lockError));
  }
  // Only a refused second daemon's message reads the pid; the lock holds without it.
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
  }
}

StorageLock::~StorageLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace slicecap::daemon
