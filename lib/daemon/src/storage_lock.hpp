// The lock that keeps a second slicecapd off a storage folder while this one lives.
#pragma once

#include <filesystem>

namespace slicecap::daemon {

/// \brief An flock on <root>/.lock, held from construction to destruction; the file holds the
/// holder's pid for a refused second daemon's message. Two daemons on one storage folder would
/// each append to the same session journal from their own idea of it and lose each other's
/// acknowledged samples. The lock goes with the process (also on SIGKILL), so a restart never
/// finds a stale one.
class StorageLock {
 public:
  /// \brief Makes the storage folder if it is missing and takes the lock; io::IoError naming the
  /// folder when it cannot be made or is not a folder, or (with the holder's pid) when another
  /// process holds it, or naming the lock file when it cannot be opened or locked.
  explicit StorageLock(const std::filesystem::path& root);
  ~StorageLock();
  StorageLock(const StorageLock&) = delete;
  StorageLock& operator=(const StorageLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace slicecap::daemon
