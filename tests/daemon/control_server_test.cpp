// The control socket under load and abuse: every client answered, the server never stops.
#include "slicecap/daemon/control_server.hpp"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "../support/test_support.hpp"
#include "slicecap/daemon/control_client.hpp"

namespace slicecap::daemon {
namespace {

using namespace std::chrono_literals;

// A daemon-like server on the test's main thread; `clients` runs on another thread, then stops it.
void serve(const std::filesystem::path& socket, RequestHandler handler,
           const std::function<void()>& clients) {
  EventLoop loop;
  const int listenFd = openListenSocket({socket, 0660, std::nullopt});
  ControlServer server(loop, listenFd, std::move(handler));
  std::exception_ptr failure;
  std::thread worker([&] {
    try {
      clients();
    } catch (...) {
      failure = std::current_exception();
    }
    loop.stop();
  });
  loop.run();
  worker.join();
  ::close(listenFd);
  if (failure) std::rethrow_exception(failure);
}

nlohmann::json echo(const Request& request) {
  if (std::holds_alternative<SessionShow>(request.command)) {
    const std::string& id = std::get<SessionShow>(request.command).id;
    if (id == "missing") throw RequestError(ErrorCode::NotFound, "no session missing");
    if (id == "bug") throw std::logic_error("a bug");
    return {{"id", id}};
  }
  return {{"command", commandName(request.command)}};
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
      ControlClient client(socket, 2s);
      return client.call(Hello{});
    } catch (const DaemonError& e) {
      if (e.code() != "unavailable" || std::chrono::steady_clock::now() > deadline) throw;
    } catch (const ConnectionError&) {
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
    ControlClient client(socket);
    EXPECT_EQ(client.call(Hello{})["command"], "hello");
    EXPECT_EQ(client.call(SessionShow{"felt"})["id"], "felt");
    try {
      client.call(SessionShow{"missing"});
      ADD_FAILURE() << "expected a refusal";
    } catch (const DaemonError& e) {
      EXPECT_EQ(e.code(), "not_found");
      EXPECT_STREQ(e.what(), "no session missing");
    }
    EXPECT_THROW(client.call(SessionShow{"bug"}), DaemonError)
        << "a handler bug is answered as internal";
    EXPECT_EQ(client.call(Status{})["command"], "status") << "and the server goes on";
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
    ControlClient after(socket);
    EXPECT_EQ(after.call(Hello{})["command"], "hello");
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
        ControlClient client(socket);
        for (int r = 0; r < 20; ++r) {
          const std::string id = "c" + std::to_string(c) + "-" + std::to_string(r);
          if (client.call(SessionShow{id})["id"] == id) ++answered;
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
        std::string(kMaxRequestBytes * 3, 'x') + "\n" + encodeRequest({7, Hello{}}) + "\n";
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
    ControlClient client(socket);
    EXPECT_EQ(client.call(Hello{})["command"], "hello");
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
    const std::string request = encodeRequest({1, Hello{}}) + "\n";
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
  const auto padded = [](const Request& request) {
    return nlohmann::json{{"command", commandName(request.command)},
                          {"pad", std::string(1000, 'x')}};
  };
  serve(socket, padded, [&] {
    const int flooder = rawConnect(socket);
    std::atomic<bool> stop = false, cutOff = false;
    std::thread writer([&] {
      std::string burst;
      while (burst.size() < 65536)
        burst += encodeRequest({1, Status{}}) + "\n";
      while (!stop) {
        if (::send(flooder, burst.data(), burst.size(), MSG_NOSIGNAL) < 0) {
          cutOff = true;
          return;
        }
      }
    });
    std::this_thread::sleep_for(100ms);
    try {
      ControlClient other(socket, 2s);
      EXPECT_EQ(other.call(Hello{})["command"], "hello");
    } catch (const ConnectionError& e) {
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

TEST(ListenSocket, ReplacesAStaleSocketButNotALiveOneOrAFile) {
  const test::SocketDir dir;
  const int first = openListenSocket({dir / "a.sock", 0660, std::nullopt});
  EXPECT_THROW(openListenSocket({dir / "a.sock", 0660, std::nullopt}), std::runtime_error)
      << "live";
  ::close(first);  // the file stays behind, as after a crash
  const int second = openListenSocket({dir / "a.sock", 0660, std::nullopt});
  EXPECT_GE(second, 0);
  ::close(second);
  std::ofstream(dir / "file.sock") << "not a socket";
  EXPECT_THROW(openListenSocket({dir / "file.sock", 0660, std::nullopt}), std::runtime_error);
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
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(name));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("longer than 107 bytes"));
  }
  try {
    ControlClient client(dir / name, 1s);
    ADD_FAILURE() << "the client connected to a path too long for a socket";
  } catch (const ConnectionError& e) {
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
