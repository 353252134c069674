// Durability tests: a child process writes and acknowledges record after record until it is
// killed with SIGKILL, as a daemon would be by kill -9 or a power cut.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <functional>

namespace slicecap::test {

/// \brief Forks a child that runs `writeForever(acknowledge)`, where the child calls
/// acknowledge() after each write it considers durable; kills the child with SIGKILL once
/// `stopAfter` acknowledgements arrived (or it died). Returns how many were acknowledged.
inline int killAfterAcknowledgements(
    int stopAfter,
    const std::function<void(const std::function<void()>& acknowledge)>& writeForever) {
  int pipeFds[2];
  if (pipe(pipeFds) != 0) {
    ADD_FAILURE() << "pipe failed";
    return 0;
  }
  const pid_t child = fork();
  if (child < 0) {
    ADD_FAILURE() << "fork failed";
    return 0;
  }
  if (child == 0) {
    close(pipeFds[0]);
    writeForever([&] {
      const char ack = 'a';
      if (write(pipeFds[1], &ack, 1) != 1) _exit(1);
    });
    _exit(0);
  }
  close(pipeFds[1]);
  int acknowledged = 0;
  char ack;
  while (acknowledged < stopAfter && read(pipeFds[0], &ack, 1) == 1)
    ++acknowledged;
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  close(pipeFds[0]);
  return acknowledged;
}

}  // namespace slicecap::test
