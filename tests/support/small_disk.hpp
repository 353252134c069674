// A small tmpfs mounted on a test's folder, to fill up like a real full disk; unmounted at the
// end. Mounting needs root (CI runs the tests as root): `mounted()` is false where it is not
// permitted, and the test skips saying so.
#pragma once

#include <sys/mount.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace slicecap::test {

class SmallDisk {
 public:
  SmallDisk(const std::filesystem::path& folder, const std::string& size) : folder_(folder) {
    std::filesystem::create_directories(folder_);
    const std::string options = "size=" + size + ",mode=0755";
    if (::mount("tmpfs", folder_.c_str(), "tmpfs", 0, options.c_str()) == 0)
      mounted_ = true;
    else
      why_ = std::strerror(errno);
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(folder_.c_str(), MNT_DETACH);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  bool mounted() const { return mounted_; }
  /// \brief Why mounting failed, for the skip message.
  const std::string& why() const { return why_; }

  /// \brief Fills the disk with `filler` until a write fails, leaving about `leaveBytes` free
  /// (removing that much again).
  void fill(const std::filesystem::path& filler, std::size_t leaveBytes) const {
    {
      std::ofstream out(filler, std::ios::binary);
      const std::vector<char> block(4096, 'x');
      while (out.write(block.data(), std::streamsize(block.size())))
        out.flush();
    }
    std::error_code error;
    const auto size = std::filesystem::file_size(filler, error);
    if (!error) std::filesystem::resize_file(filler, size > leaveBytes ? size - leaveBytes : 0);
  }

 private:
  std::filesystem::path folder_;
  bool mounted_ = false;
  std::string why_;
};

}  // namespace slicecap::test
