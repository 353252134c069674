// The control socket under load and abuse: every client answered, the server never stops.
#include "slicecap/daemon/control_server.hpp"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <future>
#include <thread>

#include "../support/request_as_user.hpp"
#include "../support/test_support.hpp"
#include "slicecap/control/control_client.hpp"
#include "slicecap/daemon/slicecapd_error.hpp"

namespace slicecap::daemon {
namespace {

using namespace std::chrono_literals;

// A daemon-like server on the test's main thread; `clients` runs on another thread (and may post
// work to the loop), then stops it.
void serve(const std::filesystem::path& socket, RequestHandler handler, ServerLimits limits,
           const std::function<void(EventLoop&)>& clients) {
  EventLoop loop;
  const ListenSocket listening({socket, 0660, std::nullopt});
  limits.socketGroup = listening.group();
  ControlServer server(loop, listening.fd(), std::move(handler), limits);
  std::exception_ptr failure;
  std::thread worker([&] {
    try {
      clients(loop);
    } catch (...) {
      failure = std::current_exception();
    }
    loop.stop();
  });
  loop.run();
  worker.join();
  if (failure) std::rethrow_exception(failure);
}

void serve(const std::filesystem::path& socket, RequestHandler handler,
           const std::function<void()>& clients) {
  serve(socket, std::move(handler), ServerLimits{}, [&](EventLoop&) { clients(); });
}

nlohmann::json echo(const control::Request& request) {
  if (std::holds_alternative<control::SessionShow>(request.command)) {
    const std::string& id = std::get<control::SessionShow>(request.command).id;
    if (id == "missing") throw RequestError(control::ErrorCode::NotFound, "no session missing");
    if (id == "bug") throw std::logic_error("a bug");
    return {{"id", id}};
  }
  return {{"command", control::commandName(request.command)}};
}

// A raw connection for sending arbitrary bytes.
int rawConnect(const std::filesystem::path& socket) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (socket.native().size() >= sizeof address.sun_path)
    throw std::runtime_error(socket.string() + ": too long for a socket");
  std::strcpy(address.sun_path, socket.c_str());
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0)
    throw std::runtime_error("connect");
  return fd;
}

// Hello on a new connection once the server has room for it. Right after a burst of clients that
// hung up, the server may still hold maxClients of them whose hang-up it has not read yet (one
// read a wake-up), and it then refuses a new client, as it should ("too many clients", or the
// connection closed before the request is sent). A server that never answers again still fails,
// after the deadline.
nlohmann::json helloOnceTheServerHasRoom(const std::filesystem::path& socket) {
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (true) {
    try {
      control::ControlClient client(socket, 2s);
      return client.call(control::Hello{});
    } catch (const control::DaemonError& e) {
      if (e.code() != "unavailable" || std::chrono::steady_clock::now() > deadline) throw;
    } catch (const control::ConnectionError&) {
      if (std::chrono::steady_clock::now() > deadline) throw;
    }
    std::this_thread::sleep_for(10ms);
  }
}

std::string readLines(int fd, int count) {
  std::string text;
  char chunk[65536];
  while (std::count(text.begin(), text.end(), '\n') < count) {
    const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
    if (n <= 0) break;
    text.append(chunk, std::size_t(n));
  }
  return text;
}

TEST(ControlServer, AnswersRequestsAndRefusalsInOrder) {
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, [&] {
    control::ControlClient client(socket);
    EXPECT_EQ(client.call(control::Hello{})["command"], "hello");
    EXPECT_EQ(client.call(control::SessionShow{"felt"})["id"], "felt");
    try {
      client.call(control::SessionShow{"missing"});
      ADD_FAILURE() << "expected a refusal";
    } catch (const control::DaemonError& e) {
      EXPECT_EQ(e.code(), "not_found");
      EXPECT_STREQ(e.what(), "no session missing");
    }
    EXPECT_THROW(client.call(control::SessionShow{"bug"}), control::DaemonError)
        << "a handler bug is answered as internal";
    EXPECT_EQ(client.call(control::Status{})["command"], "status") << "and the server goes on";
  });
}

TEST(ControlServer, SurvivesTenThousandMalformedLines) {
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, [&] {
    const int fd = rawConnect(socket);
    std::string burst;
    for (int i = 0; i < 10000; ++i) {
      switch (i % 5) {
        case 0:
          burst += "garbage " + std::to_string(i) + "\n";
          break;
        case 1:
          burst += "{\"v\":1}\n";
          break;
        case 2:
          burst += "{\"v\":1,\"id\":" + std::to_string(i) + ",\"cmd\":\"nope\"}\n";
          break;
        case 3:
          burst += std::string("\x00\xff\r\n", 4);
          break;
        default:
          burst += "{\"v\":9,\"id\":1,\"cmd\":\"status\"}\n";
      }
    }
    std::thread writer([&] { ::send(fd, burst.data(), burst.size(), MSG_NOSIGNAL); });
    const std::string answers = readLines(fd, 10000);
    writer.join();
    EXPECT_EQ(std::count(answers.begin(), answers.end(), '\n'), 10000);
    EXPECT_EQ(answers.find("\"ok\":true"), std::string::npos);
    ::close(fd);
    control::ControlClient after(socket);
    EXPECT_EQ(after.call(control::Hello{})["command"], "hello");
  });
}

TEST(ControlServer, ServesAHundredConcurrentClients) {
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, [&] {
    std::atomic<int> answered = 0;
    std::vector<std::thread> clients;
    for (int c = 0; c < 100; ++c) {
      clients.emplace_back([&, c] {
        control::ControlClient client(socket);
        for (int r = 0; r < 20; ++r) {
          const std::string id = "c" + std::to_string(c) + "-" + std::to_string(r);
          if (client.call(control::SessionShow{id})["id"] == id) ++answered;
        }
      });
    }
    for (auto& t : clients)
      t.join();
    EXPECT_EQ(answered, 2000);
  });
}

TEST(ControlServer, RefusesAnOversizedLineAndKeepsTheConnection) {
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, [&] {
    const int fd = rawConnect(socket);
    const std::string huge =
        std::string(control::kMaxRequestBytes * 3, 'x') + "\n" + control::encodeRequest({7, control::Hello{}}) + "\n";
    std::thread writer([&] { ::send(fd, huge.data(), huge.size(), MSG_NOSIGNAL); });
    const std::string answers = readLines(fd, 2);
    writer.join();
    EXPECT_NE(answers.find("too_large"), std::string::npos);
    EXPECT_NE(answers.find("\"id\":7,\"ok\":true"), std::string::npos) << answers;
    ::close(fd);
  });
}

TEST(ControlServer, ForgetsClientsThatHangUpMidLine) {
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, [&] {
    for (int i = 0; i < 50; ++i) {
      const int fd = rawConnect(socket);
      ::send(fd, "{\"v\":1,\"id\":", 12, MSG_NOSIGNAL);
      ::close(fd);
    }
    control::ControlClient client(socket);
    EXPECT_EQ(client.call(control::Hello{})["command"], "hello");
  });
}

TEST(ControlServer, AClientThatHangsUpBeforeItsAnswerIsClosedOnce) {
  // Its connection was closed twice (flush() met the broken pipe and dropped it, then the hang-up
  // dropped it again): the second close() shut whatever another thread of the daemon had opened
  // under that number in between, here a bystander's descriptor. Since the server reads a client
  // once a wake-up, a hang-up with an answer still unsent is rare, and this no longer fails when
  // drop()'s once-only check alone is taken out (0 of 20 runs); it stays as a stress test that no
  // hang-up pattern closes another thread's descriptor or stops the server.
#ifdef SLICECAP_TESTS_UNDER_EMULATOR
  // Under qemu-user 3000 connections outrun the emulated server, and the race is the emulator's.
  GTEST_SKIP() << "a descriptor race between threads: run natively";
#endif
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, [&] {
    std::atomic<bool> done = false;
    std::atomic<int> closedUnderIt = 0;
    // A connect that fails ends the test with the failure, not std::terminate of a joinable thread.
    struct StopAndJoin {
      std::atomic<bool>& done;
      std::thread& thread;
      ~StopAndJoin() {
        done = true;
        if (thread.joinable()) thread.join();
      }
    };
    std::thread bystander;
    const StopAndJoin stopBystander{done, bystander};
    bystander = std::thread([&] {
      while (!done) {
        const int mine = ::eventfd(0, EFD_CLOEXEC);
        for (int k = 0; k < 20; ++k) {
          if (::fcntl(mine, F_GETFD) < 0) {
            ++closedUnderIt;
            return;  // its number may be someone else's by now: not closed again
          }
        }
        ::close(mine);
      }
    });
    const std::string request = control::encodeRequest({1, control::Hello{}}) + "\n";
    for (int i = 0; i < 3000 && closedUnderIt == 0; ++i) {
      const int fd = rawConnect(socket);
      ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
      ::close(fd);  // before the answer
    }
    EXPECT_EQ(helloOnceTheServerHasRoom(socket)["command"], "hello");
    done = true;
    bystander.join();
    EXPECT_EQ(closedUnderIt, 0) << "a descriptor of another thread was closed by the server";
  });
}

TEST(ControlServer, AClientWritingWithoutPauseDoesNotHoldUpTheOthers) {
  // A script piping requests in without reading the answers: the server read it until it paused,
  // so nobody else was answered (nor a frame taken, nor the watchdog fed) while its unread answers
  // piled up in memory.
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  const auto padded = [](const control::Request& request) {
    return nlohmann::json{{"command", control::commandName(request.command)},
                          {"pad", std::string(1000, 'x')}};
  };
  serve(socket, padded, [&] {
    const int flooder = rawConnect(socket);
    std::atomic<bool> stop = false, cutOff = false;
    std::thread writer([&] {
      std::string burst;
      while (burst.size() < 65536)
        burst += control::encodeRequest({1, control::Status{}}) + "\n";
      while (!stop) {
        if (::send(flooder, burst.data(), burst.size(), MSG_NOSIGNAL) < 0) {
          cutOff = true;
          return;
        }
      }
    });
    std::this_thread::sleep_for(100ms);
    try {
      control::ControlClient other(socket, 2s);
      EXPECT_EQ(other.call(control::Hello{})["command"], "hello");
    } catch (const control::ConnectionError& e) {
      ADD_FAILURE() << e.what();
    }
    for (int k = 0; k < 200 && !cutOff; ++k)
      std::this_thread::sleep_for(10ms);
    EXPECT_TRUE(cutOff) << "the client that never read its answers was not dropped";
    stop = true;
    writer.join();
    ::close(flooder);
  });
}

TEST(ControlServer, ClientsThatHungUpHoldNoSlotWhenANewOneArrives) {
  // Hang-ups the loop has not read yet were counted: with the slots full of clients that had
  // gone, a new client was told "too many clients". Here the new client connects while the loop
  // is held, then the others hang up, so the loop sees the new connection before their hang-ups.
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  ServerLimits limits;
  limits.maxClients = 8;
  serve(socket, echo, limits, [&](EventLoop& loop) {
    std::vector<int> gone;
    const std::string hello = control::encodeRequest({1, control::Hello{}}) + "\n";
    for (std::size_t i = 0; i < limits.maxClients; ++i) {
      gone.push_back(rawConnect(socket));
      ::send(gone.back(), hello.data(), hello.size(), MSG_NOSIGNAL);
      ASSERT_THAT(readLines(gone.back(), 1), ::testing::HasSubstr("\"ok\":true"));  // accepted
    }
    std::promise<void> release;
    std::promise<void> held;
    loop.post([&] {
      held.set_value();
      release.get_future().wait();
    });
    held.get_future().wait();
    const int late = rawConnect(socket);  // waits in the backlog: the loop is held
    for (const int fd : gone)
      ::close(fd);
    release.set_value();
    const std::string request = control::encodeRequest({2, control::Hello{}}) + "\n";
    ::send(late, request.data(), request.size(), MSG_NOSIGNAL);
    const std::string answer = readLines(late, 1);
    EXPECT_THAT(answer, ::testing::HasSubstr("\"id\":2,\"ok\":true")) << answer;
    ::close(late);
  });
}

TEST(ControlServer, IdleClientsAreClosedSoTheyCannotHoldEverySlot) {
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  ServerLimits limits;
  limits.maxClients = 4;
  limits.idleTimeout = 50ms;
  serve(socket, echo, limits, [&](EventLoop&) {
    std::vector<int> idle;
    for (std::size_t i = 0; i < limits.maxClients; ++i)
      idle.push_back(rawConnect(socket));
    // Each idle client is told why and closed: it reads the line, then the end of the stream.
    for (const int fd : idle) {
      timeval deadline{10, 0};
      ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &deadline, sizeof deadline);
      const std::string said = readLines(fd, 1);
      EXPECT_THAT(said, ::testing::HasSubstr("without a request")) << said;
      char byte;
      EXPECT_EQ(::recv(fd, &byte, 1, 0), 0) << "still open";
      ::close(fd);
    }
    EXPECT_EQ(helloOnceTheServerHasRoom(socket)["command"], "hello");
  });
}

TEST(PeerPolicy, RootTheDaemonsUidAndTheSocketsGroupMayConnect) {
  const std::uint32_t self = 990, group = 991;
  EXPECT_TRUE(peerMayConnect({1, 0, 0}, {}, group, self)) << "root";
  EXPECT_TRUE(peerMayConnect({1, self, 100}, {}, group, self)) << "the daemon's own uid";
  EXPECT_TRUE(peerMayConnect({1, 1000, group}, {}, group, self)) << "primary group";
  EXPECT_TRUE(peerMayConnect({1, 1000, 1000}, {27, group}, group, self)) << "supplementary group";
  EXPECT_FALSE(peerMayConnect({1, 1000, 1000}, {27, 100}, group, self)) << "not in the group";
  EXPECT_FALSE(peerMayConnect({1, 1000, 991}, {991}, std::nullopt, self)) << "no group: nobody";
}

TEST(ControlServer, RefusesAPeerOutsideTheSocketsGroupEvenIfItCouldConnect) {
  // Connecting needs write permission on the socket file, which is the group's; a client that got
  // in while the file's mode was wider (the old chmod after bind, or a mode set by hand) is still
  // not served. Here the mode is widened by hand; the peer's credentials decide.
  if (!test::canChangeUser()) GTEST_SKIP() << "needs root to run a client as another user";
  const test::SocketDir sockets;
  const auto socket = sockets / "ctl.sock";
  serve(socket, echo, ServerLimits{}, [&](EventLoop&) {
    ASSERT_EQ(::chmod(sockets.path().c_str(), 0711), 0);
    ASSERT_EQ(::chmod(socket.c_str(), 0666), 0);
    struct stat file {};
    ASSERT_EQ(::stat(socket.c_str(), &file), 0);
    const gid_t group = file.st_gid, nobody = 65534;
    ASSERT_NE(group, nobody);
    const std::string hello = control::encodeRequest({3, control::Hello{}});
    const std::string outsider = test::requestAsUser(socket, nobody, nobody, {}, hello);
    EXPECT_THAT(outsider, ::testing::HasSubstr("permission_denied")) << outsider;
    EXPECT_THAT(outsider, ::testing::HasSubstr("uid 65534")) << outsider;
    EXPECT_THAT(test::requestAsUser(socket, nobody, group, {}, hello),
                ::testing::HasSubstr("\"id\":3,\"ok\":true"))
        << "a member by its primary group";
    EXPECT_THAT(test::requestAsUser(socket, nobody, nobody, {group}, hello),
                ::testing::HasSubstr("\"id\":3,\"ok\":true"))
        << "a member by a supplementary group";
  });
}

TEST(ListenSocket, IsNeverReachableWithAWiderModeWhateverTheUmask) {
  // Bound at its path and then chmod-ed, the socket was 0777 under umask 000 until the chmod:
  // another uid connected in that window (3 of 20 starts) and stayed connected.
  const test::SocketDir dir;
  const auto path = dir / "u.sock";
  int calls = 0;
  ListenSpec spec{path, 0660, std::nullopt, [&](const std::filesystem::path& bound) {
                    ++calls;
                    struct stat node {
                    }, folder{};
                    ASSERT_EQ(::stat(bound.c_str(), &node), 0);
                    ASSERT_EQ(::stat(bound.parent_path().c_str(), &folder), 0);
                    // Reachable by others: at its own path (its folder is the test's, 0700 but
                    // the daemon's is not), or in a folder others may enter.
                    const bool reachable = bound == path || (folder.st_mode & 0077) != 0;
                    if (reachable) {
                      EXPECT_EQ(node.st_mode & 0117, 0u) << bound << " is reachable with mode "
                                                         << std::oct << (node.st_mode & 07777);
                    }
                    EXPECT_FALSE(std::filesystem::exists(path))
                        << "at the socket's path before its mode is set";
                  }};
  const mode_t saved = ::umask(0);
  std::optional<ListenSocket> listening;
  try {
    listening.emplace(spec);
  } catch (...) {
    ::umask(saved);
    throw;
  }
  ::umask(saved);
  EXPECT_EQ(calls, 1);
  struct stat placed {};
  ASSERT_EQ(::stat(path.c_str(), &placed), 0);
  EXPECT_TRUE(S_ISSOCK(placed.st_mode));
  EXPECT_EQ(placed.st_mode & 07777, 0660u);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                          std::filesystem::directory_iterator()),
            1)
      << "the private folder it was bound in is gone";
  control::ControlClient client(path, 1s);  // connectable where it was put
}

TEST(ListenSocket, RemovesTheSocketFileItBoundButNotOneThatReplacedIt) {
  const test::SocketDir dir;
  const auto path = dir / "r.sock";
  { const ListenSocket listening({path, 0660, std::nullopt}); }
  EXPECT_FALSE(std::filesystem::exists(path)) << "left behind on close";
  {
    std::optional<ListenSocket> first;
    first.emplace(ListenSpec{path, 0660, std::nullopt, {}});
    std::filesystem::remove(path);
    const ListenSocket second({path, 0660, std::nullopt});
    first.reset();
    EXPECT_TRUE(std::filesystem::exists(path)) << "the first one's close took the second's file";
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  {
    const ListenSocket replaced({path, 0660, std::nullopt});
    std::filesystem::remove(path);
    std::ofstream(path) << "someone else's";
  }
  EXPECT_TRUE(std::filesystem::is_regular_file(path)) << "a file that replaced it was removed";
  std::filesystem::remove(path);
  const int released = openListenSocket({path, 0660, std::nullopt});
  ::close(released);
  EXPECT_TRUE(std::filesystem::exists(path)) << "a released descriptor's file is the caller's";
}

TEST(ListenSocket, ReplacesAStaleSocketButNotALiveOneOrAFile) {
  const test::SocketDir dir;
  const int first = openListenSocket({dir / "a.sock", 0660, std::nullopt});
  EXPECT_THROW(openListenSocket({dir / "a.sock", 0660, std::nullopt}), daemon::SlicecapdError)
      << "live";
  ::close(first);  // the file stays behind, as after a crash
  const int second = openListenSocket({dir / "a.sock", 0660, std::nullopt});
  EXPECT_GE(second, 0);
  ::close(second);
  std::ofstream(dir / "file.sock") << "not a socket";
  EXPECT_THROW(openListenSocket({dir / "file.sock", 0660, std::nullopt}), daemon::SlicecapdError);
  EXPECT_EQ(
      std::filesystem::status(dir / "a.sock").permissions() & std::filesystem::perms::others_all,
      std::filesystem::perms::none);
}

TEST(ListenSocket, APathTooLongForASocketIsRefusedByNameOnBothSides) {
  // sun_path holds 107 bytes: a longer --socket must not be cut short (another file) or overrun.
  const test::SocketDir dir;
  const std::string name = std::string(120, 's') + ".sock";
  try {
    openListenSocket({dir / name, 0660, std::nullopt});
    ADD_FAILURE() << "a " << (dir / name).native().size() << "-byte socket path was accepted";
  } catch (const daemon::SlicecapdError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(name));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("longer than 107 bytes"));
  }
  try {
    control::ControlClient client(dir / name, 1s);
    ADD_FAILURE() << "the client connected to a path too long for a socket";
  } catch (const control::ConnectionError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(name));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("too long"));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "nothing made under a shortened name";
}

TEST(EventLoop, RunsTimersPostedWorkAndSignals) {
  EventLoop loop({SIGUSR1});
  int ticks = 0, once = 0, signals = 0;
  bool posted = false;
  const auto repeating = loop.addTimer(2ms, true, [&] { ++ticks; });
  loop.addTimer(1ms, false, [&] { ++once; });
  loop.onSignal([&](int s) {
    if (s == SIGUSR1) ++signals;
  });
  std::thread other([&] {
    std::this_thread::sleep_for(20ms);
    loop.post([&] { posted = true; });
    ::kill(::getpid(), SIGUSR1);
    std::this_thread::sleep_for(20ms);
    loop.stop();
  });
  loop.run();
  other.join();
  loop.cancelTimer(repeating);
  EXPECT_GE(ticks, 3);
  EXPECT_EQ(once, 1);
  EXPECT_TRUE(posted);
  EXPECT_EQ(signals, 1);
}

// A thread started before the loop exists (libcamera's, in slicecapd) must not take the loop's
// signal: its default action would end the process. Run in a child, where that shows as a death.
TEST(EventLoop, ASignalBlockedBeforeAThreadStartsReachesTheLoopNotTheThread) {
  EXPECT_EXIT(
      {
        blockSignalsInThisAndLaterThreads({SIGUSR2});
        std::atomic<bool> done{false};
        std::thread early([&] {
          while (!done)
            std::this_thread::sleep_for(1ms);
        });
        int received = 0;
        {
          EventLoop loop({SIGUSR2});
          loop.onSignal([&](int s) {
            if (s == SIGUSR2) ++received;
            loop.stop();
          });
          loop.addTimer(5ms, false, [] { ::kill(::getpid(), SIGUSR2); });
          loop.addTimer(2s, false, [&] { loop.stop(); });
          loop.run();
        }
        done = true;
        early.join();
        std::_Exit(received == 1 ? 0 : 3);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace slicecap::daemon
