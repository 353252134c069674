// One event loop for the daemon: file descriptors, timers, signals and work posted from other
// threads.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace slicecap::daemon {

/// \brief Blocks `signals` in the calling thread; threads it starts afterwards inherit the block.
/// A process-directed signal goes to any thread that does not block it, where its default action
/// (for SIGTERM: end the process) runs before an EventLoop's signalfd sees it. So a program whose
/// libraries start threads before its EventLoop exists (libcamera's CameraManager does, in the
/// camera's constructor) calls this first. Throws std::system_error.
void blockSignalsInThisAndLaterThreads(const std::vector<int>& signals);

/// \brief An epoll loop on one thread. Signals given to the constructor are blocked in the calling
/// thread and delivered through a signalfd, so a handler runs on the loop like any other event.
/// Every method except post() and stop() must be called on the loop's thread. Constructor failures
/// throw std::system_error.
class EventLoop {
 public:
  using FdHandler = std::function<void(std::uint32_t epollEvents)>;
  using TimerId = int;

  explicit EventLoop(std::vector<int> signals = {});
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  /// \brief Calls `handler` with the epoll events (EPOLLIN, EPOLLOUT, EPOLLHUP, ...) when fd is
  /// ready.
  void watch(int fd, std::uint32_t events, FdHandler handler);
  void modify(int fd, std::uint32_t events);
  void unwatch(int fd);

  /// \brief Calls `callback` after `delay`, then every `delay` if `repeat`. Returns an id for
  /// cancel.
  TimerId addTimer(std::chrono::microseconds delay, bool repeat, std::function<void()> callback);
  void cancelTimer(TimerId id);

  /// \brief Called on the loop for each signal passed to the constructor.
  void onSignal(std::function<void(int signalNumber)> handler) {
    signalHandler_ = std::move(handler);
  }

  /// \brief Thread-safe: runs `work` on the loop's thread soon (e.g. a frame from a camera thread).
  void post(std::function<void()> work);

  /// \brief Runs until stop(). Exceptions from handlers propagate out of run().
  void run();
  /// \brief Thread-safe: makes run() return after the current event.
  void stop();

 private:
  void drainPosted();
  int epollFd_ = -1;
  int signalFd_ = -1;
  int wakeFd_ = -1;
  bool running_ = false;
  std::map<int, std::shared_ptr<FdHandler>> handlers_;
  std::map<TimerId, int> timerFds_;
  TimerId nextTimer_ = 1;
  std::function<void(int)> signalHandler_;
  std::mutex postedMutex_;
  std::vector<std::function<void()>> posted_;
  bool stopRequested_ = false;
};

}  // namespace slicecap::daemon
