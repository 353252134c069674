// The measured configuration: the guard it implies, and its atomic write.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "slicecap/hwcheck/hardware_check.hpp"
#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {

double guardFor(double offsetUs, double residualUs) {
  // The daemon treats a switch as uncertain this long either side of its record: it must cover
  // where the light really changes (the offset) and how much that wanders (the residual).
  const double needed = std::abs(offsetUs) + 3.0 * residualUs + 50.0;
  return std::max(200.0, std::ceil(needed / 10.0) * 10.0);
}

void writeConfigFile(const std::string& path, const std::string& text, bool overwrite) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::string temp = (folder / ("." + target.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0)
    throw HardwareCheckError(path + ": cannot create a file in " + folder.string() + ": " +
                             std::strerror(errno));
  const auto fail = [&](const std::string& what) {
    const int saved = errno;
    ::unlink(temp.c_str());
    throw HardwareCheckError(path + ": " + what + ": " + std::strerror(saved));
  };
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      ::close(fd);
      fail("cannot write");
    }
    written += std::size_t(n);
  }
  if (::fchmod(fd, 0644) != 0 || ::fsync(fd) != 0) {
    ::close(fd);
    fail("cannot flush");
  }
  ::close(fd);
  if (overwrite) {
    if (::rename(temp.c_str(), path.c_str()) != 0) fail("cannot replace");
    return;
  }
  // link() fails with EEXIST instead of replacing: no window in which another file is clobbered.
  if (::link(temp.c_str(), path.c_str()) != 0) {
    if (errno == EEXIST) {
      ::unlink(temp.c_str());
      throw HardwareCheckError(path + " exists: not overwritten (pass --overwrite, or choose "
                               "another file and merge its lines into slicecapd.conf)");
    }
    fail("cannot create");
  }
  ::unlink(temp.c_str());
}

}  // namespace slicecap::hwcheck
