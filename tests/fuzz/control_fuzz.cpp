// libFuzzer target: any bytes sent on slicecapd's control socket, as one client would send them,
// to a whole Daemon (the socket framing of ControlServer, parseRequest, the daemon's handling and
// SessionManager's state machine) with a session open and a camera that delivers a few frames.
// The daemon must answer or refuse every line, never crash, and stop cleanly afterwards.
//
// Safety: requests are handled with this process's rights, and a fuzzed `export` may name any
// folder. Lines exporting anywhere but into the fuzz storage are left out before they are sent,
// and the storage is a fixed folder (run one fuzzing process at a time).
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <future>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "../support/daemon_fakes.hpp"
#include "slicecap/daemon/daemon.hpp"
#include "slicecap/control/protocol.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/file_led.hpp"

namespace {

namespace fs = std::filesystem;
using namespace slicecap;

fs::path fuzzRoot() {
  static const fs::path root =
      fs::path(fs::is_directory("/dev/shm") ? "/dev/shm" : "/tmp") / "slicecap-control-fuzz";
  return root;
}

// A live camera with a few frames, LED on and off in turn, then the end of its stream.
class FewFramesCamera : public hal::Camera {
 public:
  FewFramesCamera() : ready_(::eventfd(1, EFD_NONBLOCK | EFD_CLOEXEC)) {}
  ~FewFramesCamera() override { ::close(ready_); }
  std::string id() const override { return "fuzz"; }
  hal::ConfigResult configure(hal::CameraConfig&) override { return {}; }
  void start() override { sent_ = 0; }
  void stop() override {}
  std::optional<int> readyDescriptor() const override { return ready_; }
  hal::ExposureLock lockExposure(const hal::ExposureSetting& wanted) override {
    return {hal::ExposureSetting{wanted.exposureUs, wanted.gain.value_or(1.0)}, ""};
  }
  hal::CaptureResult nextFrame(std::chrono::milliseconds) override {
    if (sent_ >= 6) return {hal::CaptureResult::Status::EndOfStream, {}, ""};
    hal::Frame frame;
    frame.encoding = PixelEncoding::Linear16;
    frame.image = {8, 8, 3, 16, std::vector<std::uint16_t>(8 * 8 * 3, 20000)};
    frame.metadata = {sequence_, std::int64_t(sequence_) * 33'000, 8000.0, 1.0, sent_ % 2 == 0, 0};
    ++sequence_;
    ++sent_;
    return {hal::CaptureResult::Status::Frame, std::move(frame), ""};
  }

 private:
  int ready_;
  std::uint64_t sequence_ = 0;
  int sent_ = 0;
};

// A sample for each LED-on frame, spread over the azimuth bins.
capture::FrameProcessor standInPipeline() {
  return [](const hal::Frame& frame, const SliceId& slice) {
    capture::FrameOutcome outcome;
    if (!frame.metadata.ledOn) {
      outcome.kind = capture::FrameOutcome::Kind::Ambient;
      return outcome;
    }
    const double phi = double(frame.metadata.sequence / 2 % 24) * 15.0;
    outcome.kind = capture::FrameOutcome::Kind::Sample;
    outcome.sample = capture::FrameSample{frame.metadata.timestampUs,
                                          frame.metadata.sequence,
                                          {double(slice.elevations.thetaIDeg), phi},
                                          {double(slice.elevations.thetaVDeg), phi + 15},
                                          Rgb::gray(0.3)};
    return outcome;
  };
}

// Whether a line may be sent: any line but an export into a folder outside the fuzz storage.
bool safeToSend(std::string_view line, const fs::path& storage) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  const auto parsed = control::parseRequest(line);
  const auto* request = std::get_if<control::Request>(&parsed);
  if (!request) return true;
  const auto* exporting = std::get_if<control::Export>(&request->command);
  if (!exporting || exporting->directory.empty()) return true;
  const std::string& directory = exporting->directory;
  return directory.rfind(storage.string() + "/", 0) == 0 &&
         directory.find("..") == std::string::npos;
}

int connectTo(const fs::path& socket) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strcpy(address.sun_path, socket.c_str());
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    std::cerr << "control_fuzz: cannot connect to " << socket << ": " << std::strerror(errno)
              << "\n";
    std::abort();
  }
  return fd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slicecap::daemon;
  static hal::SteadyClock clock;
  const fs::path root = fuzzRoot(), storage = root / "storage", socket = root / "s.sock";
  std::error_code ignored;
  fs::remove_all(storage, ignored);
  fs::create_directories(storage);

  // The session is opened and a sweep started before the fuzzed bytes, on the same connection.
  std::string input =
      control::encodeRequest({-1, control::SessionNew{"fuzz", std::string("fuzz")}}) + "\n" +
      control::encodeRequest({-2, control::SweepStart{{SliceKind::Axial, {30, 30}}}}) + "\n";
  const std::string_view fuzzed(reinterpret_cast<const char*>(data), size);
  for (std::size_t start = 0; start < fuzzed.size();) {
    const std::size_t newline = fuzzed.find('\n', start);
    const std::size_t end = newline == std::string_view::npos ? fuzzed.size() : newline + 1;
    const std::string_view line = fuzzed.substr(start, end - start);
    // A line longer than the limit is refused unread, whatever it holds.
    if (line.size() > control::kMaxRequestBytes ||
        safeToSend(line.substr(0, line.size() - (newline == std::string_view::npos ? 0 : 1)),
                   storage))
      input += line;
    else
      input += "\n";
    start = end;
  }

  const ListenSocket listening({socket, 0600, std::nullopt, {}});
  std::promise<Daemon*> made;
  std::thread server([&] {
    // Made on this thread: its EventLoop blocks the stop signals here, not in libFuzzer's thread
    // (whose SIGALRM catches a slow input).
    DaemonParts parts;
    parts.storage = storage;
    auto camera = std::make_shared<FewFramesCamera>();
    parts.rig = std::make_unique<test::OneCameraRig>(
        [camera] { return camera; },
        [](capture::FrameObserver) { return capture::settledAtOnce(standInPipeline()); });
    parts.cameraConfig.exposureUs = 8000.0;
    parts.led = std::make_unique<hal::FileLed>(root / "led.log", clock);
    parts.tables = std::make_unique<test::EmptyTables>();
    std::optional<Daemon> daemon;
    try {
      daemon.emplace(std::move(parts), listening.fd());
    } catch (...) {
      made.set_exception(std::current_exception());
      return;
    }
    made.set_value(&*daemon);
    daemon->run();
  });
  Daemon* daemon = made.get_future().get();
  const int fd = connectTo(socket);
  std::thread writer([&] {
    [[maybe_unused]] const auto sent = ::send(fd, input.data(), input.size(), MSG_NOSIGNAL);
    ::shutdown(fd, SHUT_WR);
  });
  // Every answer, until the daemon closes the connection (it read the end of the input).
  char buffer[65536];
  while (::recv(fd, buffer, sizeof buffer, 0) > 0) {
  }
  writer.join();
  ::close(fd);
  daemon->stop();
  server.join();
  return 0;
}
