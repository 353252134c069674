// epoll-based event loop with signalfd, timerfd and an eventfd for cross-thread posts.
#include "slicecap/daemon/event_loop.hpp"

#include <signal.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace slicecap::daemon {
namespace {

std::system_error lastError(const char* what) {
  return std::system_error(errno, std::generic_category(), what);
}

sigset_t signalSet(const std::vector<int>& signals) {
  sigset_t set;
  sigemptyset(&set);
  for (int s : signals)
    sigaddset(&set, s);
  return set;
}

}  // namespace

void blockSignalsInThisAndLaterThreads(const std::vector<int>& signals) {
  const sigset_t set = signalSet(signals);
  // pthread_sigmask returns the error number instead of setting errno.
  if (const int error = pthread_sigmask(SIG_BLOCK, &set, nullptr); error != 0)
    throw std::system_error(error, std::generic_category(), "pthread_sigmask");
}

EventLoop::EventLoop(std::vector<int> signals) {
  epollFd_ = epoll_create1(EPOLL_CLOEXEC);
  if (epollFd_ < 0) throw lastError("epoll_create1");
  wakeFd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wakeFd_ < 0) throw lastError("eventfd");
  watch(wakeFd_, EPOLLIN, [this](std::uint32_t) {
    std::uint64_t count;
    while (::read(wakeFd_, &count, sizeof count) > 0) {
    }
    drainPosted();
  });
  if (!signals.empty()) {
    blockSignalsInThisAndLaterThreads(signals);
    const sigset_t mask = signalSet(signals);
    signalFd_ = signalfd(-1, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
    if (signalFd_ < 0) throw lastError("signalfd");
    watch(signalFd_, EPOLLIN, [this](std::uint32_t) {
      signalfd_siginfo info;
      while (::read(signalFd_, &info, sizeof info) == sizeof info) {
        if (signalHandler_) signalHandler_(int(info.ssi_signo));
      }
    });
  }
}

EventLoop::~EventLoop() {
  for (const auto& [id, fd] : timerFds_)
    ::close(fd);
  if (signalFd_ >= 0) ::close(signalFd_);
  if (wakeFd_ >= 0) ::close(wakeFd_);
  if (epollFd_ >= 0) ::close(epollFd_);
}

void EventLoop::watch(int fd, std::uint32_t events, FdHandler handler) {
  epoll_event event{};
  event.events = events;
  event.data.fd = fd;
  if (epoll_ctl(epollFd_, EPOLL_CTL_ADD, fd, &event) != 0) throw lastError("epoll_ctl ADD");
  handlers_[fd] = std::make_shared<FdHandler>(std::move(handler));
}

void EventLoop::modify(int fd, std::uint32_t events) {
  epoll_event event{};
  event.events = events;
  event.data.fd = fd;
  if (epoll_ctl(epollFd_, EPOLL_CTL_MOD, fd, &event) != 0) throw lastError("epoll_ctl MOD");
}

void EventLoop::unwatch(int fd) {
  epoll_ctl(epollFd_, EPOLL_CTL_DEL, fd, nullptr);
  handlers_.erase(fd);
}

EventLoop::TimerId EventLoop::addTimer(std::chrono::microseconds delay, bool repeat,
                                       std::function<void()> callback) {
  const int fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (fd < 0) throw lastError("timerfd_create");
  const auto micros = std::max<std::int64_t>(delay.count(), 1);
  itimerspec spec{};
  spec.it_value = {time_t(micros / 1000000), long(micros % 1000000) * 1000};
  if (repeat) spec.it_interval = spec.it_value;
  if (timerfd_settime(fd, 0, &spec, nullptr) != 0) {
    ::close(fd);
    throw lastError("timerfd_settime");
  }
  const TimerId id = nextTimer_++;
  timerFds_[id] = fd;
  watch(fd, EPOLLIN, [this, fd, id, repeat, callback = std::move(callback)](std::uint32_t) {
    std::uint64_t expirations;
    if (::read(fd, &expirations, sizeof expirations) != sizeof expirations) return;
    if (!repeat) cancelTimer(id);
    callback();
  });
  return id;
}

void EventLoop::cancelTimer(TimerId id) {
  auto it = timerFds_.find(id);
  if (it == timerFds_.end()) return;
  unwatch(it->second);
  ::close(it->second);
  timerFds_.erase(it);
}

void EventLoop::post(std::function<void()> work) {
  {
    std::lock_guard lock(postedMutex_);
    posted_.push_back(std::move(work));
  }
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto written = ::write(wakeFd_, &one, sizeof one);
}

void EventLoop::drainPosted() {
  std::vector<std::function<void()>> work;
  {
    std::lock_guard lock(postedMutex_);
    work.swap(posted_);
  }
  for (auto& w : work)
    w();
}

void EventLoop::stop() {
  post([this] { stopRequested_ = true; });
}

void EventLoop::run() {
  stopRequested_ = false;
  epoll_event events[32];
  while (!stopRequested_) {
    const int count = epoll_wait(epollFd_, events, 32, -1);
    if (count < 0) {
      if (errno == EINTR) continue;
      throw lastError("epoll_wait");
    }
    for (int i = 0; i < count && !stopRequested_; ++i) {
      auto it = handlers_.find(events[i].data.fd);
      if (it == handlers_.end()) continue;  // unwatched by an earlier handler of this round
      const std::shared_ptr<FdHandler> handler =
          it->second;  // keeps it alive if it unwatches itself
      (*handler)(events[i].events);
    }
  }
}

}  // namespace slicecap::daemon
