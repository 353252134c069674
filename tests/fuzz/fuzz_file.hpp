// Helpers of the libFuzzer targets whose reader takes a path: a scratch folder of this process
// under /dev/shm (memory, so the thousands of writes a second do not touch a disk), removed at
// exit, and writing the input into a fixed file there.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

namespace slicecap::fuzz {

/// \brief /dev/shm/slicecap-fuzz-NAME-PID (the system's temporary folder without /dev/shm),
/// created on the first call and removed when the process exits normally.
inline const std::filesystem::path& scratchDir(const std::string& name) {
  static const std::filesystem::path dir = [&] {
    std::error_code error;
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", error)
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    std::filesystem::path made =
        base / ("slicecap-fuzz-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(made, error);
    std::filesystem::create_directories(made);
    return made;
  }();
  static const bool cleanupRegistered = [] {
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    });
    return true;
  }();
  (void)cleanupRegistered;
  return dir;
}

/// \brief Replaces `path` with the bytes.
inline void writeBytes(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) std::abort();  // the harness's own failure, not the reader's
}

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace slicecap::fuzz
