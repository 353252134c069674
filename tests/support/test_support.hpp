// Helpers shared by the tests: a fresh temporary directory, the optional shared data folder.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "slicecap/core/abrdf.hpp"

namespace slicecap::test {

/// \brief A directory unique to the running test, emptied on creation.
inline std::filesystem::path freshTempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(SLICECAP_TEST_TMP_DIR) /
                              (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// \brief A fresh directory under /tmp for Unix sockets, removed with this object.
///
/// A socket's path must fit sun_path (107 bytes). freshTempDir()'s, with the build tree and the
/// test's name in it, does not in a deep checkout: CI's clone put the arm64 tree's past it, and
/// the control-socket tests failed there on "socket path longer than 107 bytes".
/// \throws std::runtime_error when the directory cannot be made.
class SocketDir {
 public:
  SocketDir() {
    char pattern[] = "/tmp/slicecap-sock-XXXXXX";
    if (!::mkdtemp(pattern))
      throw std::runtime_error(std::string("cannot make a socket directory in /tmp: ") +
                               std::strerror(errno));
    dir_ = pattern;
  }
  ~SocketDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  SocketDir(const SocketDir&) = delete;
  SocketDir& operator=(const SocketDir&) = delete;

  std::filesystem::path operator/(const std::string& name) const { return dir_ / name; }
  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

/// \brief The nbrdf-bonn81 folder of ../shared/data (or $SLICECAP_SHARED_DATA), if present.
inline std::optional<std::filesystem::path> sharedTablesDir() {
  std::filesystem::path base = SLICECAP_SHARED_DATA_DIR;
  if (const char* overrideDir = std::getenv("SLICECAP_SHARED_DATA")) base = overrideDir;
  const std::filesystem::path dir = base / "nbrdf-bonn81";
  if (std::filesystem::is_directory(dir)) return dir;
  return std::nullopt;
}

/// \brief Largest absolute difference between two tables.
inline double maxAbsDifference(const Abrdf& a, const Abrdf& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.values().size(); ++i) {
    worst = std::max(worst, double(std::abs(a.values()[i] - b.values()[i])));
  }
  return worst;
}

}  // namespace slicecap::test

/// Skips the current test with a clear message when ../shared/data is absent (a user's clone).
#define SLICECAP_REQUIRE_SHARED_DATA(dirVariable)                                                  \
  const auto dirVariable##Optional = ::slicecap::test::sharedTablesDir();                          \
  if (!dirVariable##Optional) {                                                                    \
    GTEST_SKIP() << "../shared/data/nbrdf-bonn81 is absent (set SLICECAP_SHARED_DATA to a folder " \
                    "holding it); this test needs the measured-material tables";                   \
  }                                                                                                \
  const std::filesystem::path dirVariable = *dirVariable##Optional
