// Runs a piece of a test in a child process whose address space is limited, so that an allocation
// of gigabytes fails there (std::bad_alloc) instead of succeeding on a large machine.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <functional>

namespace slicecap::test {

/// \brief Forks; the child limits its address space to what it uses now plus `extraBytes`, runs
/// `body` and exits with its result (0..255). Returns the child's exit code, or -1 when it did
/// not exit normally (e.g. a crash).
inline int exitCodeWithMemoryLimit(std::size_t extraBytes, const std::function<int()>& body) {
  const pid_t child = fork();
  if (child < 0) return -1;
  if (child == 0) {
    std::size_t pages = 0;
    std::ifstream("/proc/self/statm") >> pages;
    const rlim_t limit = pages * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + extraBytes;
    const rlimit asLimit{limit, limit};
    if (setrlimit(RLIMIT_AS, &asLimit) != 0) _exit(250);
    _exit(body());
  }
  int status = 0;
  if (waitpid(child, &status, 0) != child || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace slicecap::test
