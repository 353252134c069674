// The record journal and atomic file replacement, on POSIX file descriptors for explicit syncs.
#include "slicecap/io/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

IoError systemError(const std::filesystem::path& path, const std::string& what) {
  return IoError(path.string() + ": " + what + ": " + std::strerror(errno));
}

// Writes all bytes, retrying short writes and EINTR; false on error (errno set).
bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    size -= std::size_t(n);
  }
  return true;
}

std::string hex8(std::uint32_t value) {
  char text[9];
  std::snprintf(text, sizeof text, "%08x", value);
  return text;
}

void syncDirectory(const std::filesystem::path& directory) {
  const int fd =
      ::open(directory.empty() ? "." : directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw systemError(directory, "cannot open folder to sync it");
  const int result = ::fsync(fd);
  ::close(fd);
  if (result != 0) throw systemError(directory, "cannot sync folder");
}

// Writes a whole file and syncs it to disk before it replaces anything: after a power cut the
// renamed file is complete. IoError naming the file.
void writeSynced(const std::filesystem::path& path, std::string_view contents) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640);
  if (fd < 0) throw systemError(path, "cannot create");
  if (!writeAll(fd, contents.data(), contents.size()) || ::fsync(fd) != 0) {
    const IoError error = systemError(path, "cannot write");
    ::close(fd);
    throw error;
  }
  if (::close(fd) != 0) throw systemError(path, "cannot write");
}

}  // namespace

std::uint32_t crc32(std::string_view bytes) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k)
        c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char b : bytes)
    crc = table[(crc ^ b) & 0xFF] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

Journal::Journal(std::filesystem::path path, int fd, std::uint64_t size)
    : path_(std::move(path)), fd_(fd), size_(size) {}

Journal::Journal(Journal&& other) noexcept
    : path_(std::move(other.path_)), fd_(other.fd_), size_(other.size_) {
  other.fd_ = -1;
}

Journal& Journal::operator=(Journal&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    size_ = other.size_;
    other.fd_ = -1;
  }
  return *this;
}

Journal::~Journal() {
  if (fd_ >= 0) ::close(fd_);
}

std::filesystem::path tornTailFile(const std::filesystem::path& journal) {
  return journal.string() + ".torn";
}

Journal Journal::open(const std::filesystem::path& path, std::vector<std::string>* records,
                      JournalRecovery* recovery) {
  std::vector<JournalLine> lines;
  Journal journal = openLines(path, &lines, recovery);
  if (records)
    for (JournalLine& line : lines)
      if (line.intact) records->push_back(std::move(line.text));
  return journal;
}

Journal Journal::openLines(const std::filesystem::path& path, std::vector<JournalLine>* lines,
                           JournalRecovery* recovery) {
  const bool existed = std::filesystem::exists(path);
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0640);
  if (fd < 0) throw systemError(path, "cannot open journal");
  Journal journal(path, fd, 0);
  if (!existed) syncDirectory(path.parent_path());

  std::string contents;
  char buffer[65536];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw systemError(path, "cannot read journal");
    if (n == 0) break;
    contents.append(buffer, std::size_t(n));
  }
  JournalRecovery found;
  std::size_t lineStart = 0, lineNumber = 0;
  while (lineStart < contents.size()) {
    const std::size_t newline = contents.find('\n', lineStart);
    if (newline == std::string::npos) break;  // torn tail, handled below
    ++lineNumber;
    const std::string_view line(contents.data() + lineStart, newline - lineStart);
    const bool wellFormed = line.size() >= 9 && line[8] == ' ';
    const std::string_view record = wellFormed ? line.substr(9) : line;
    const bool intact = wellFormed && hex8(crc32(record)) == line.substr(0, 8);
    if (intact)
      ++found.records;
    else
      found.corruptLines.push_back(lineNumber);
    if (lines) lines->push_back({lineNumber, std::string(record), intact});
    lineStart = newline + 1;
  }
  found.tornTailBytes = contents.size() - lineStart;
  if (found.tornTailBytes > 0) {
    // Never acknowledged (append returns after the sync), yet kept: what was on disk is not
    // deleted, and the file tells the reader that a write was cut short.
    const std::filesystem::path kept = tornTailFile(path);
    const int keptFd = ::open(kept.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0640);
    if (keptFd < 0) throw systemError(kept, "cannot keep the torn record");
    const bool keptOk =
        writeAll(keptFd, contents.data() + lineStart, found.tornTailBytes) && ::fsync(keptFd) == 0;
    const IoError keptError = systemError(kept, "cannot keep the torn record");
    ::close(keptFd);
    if (!keptOk) throw keptError;
    syncDirectory(path.parent_path());
    if (::ftruncate(fd, off_t(lineStart)) != 0 || ::fsync(fd) != 0)
      throw systemError(path, "cannot cut torn record");
  }
  journal.size_ = lineStart;
  if (::lseek(fd, off_t(lineStart), SEEK_SET) < 0) throw systemError(path, "cannot seek journal");
  if (recovery) *recovery = found;
  return journal;
}

void Journal::append(std::string_view record) {
  if (record.find('\n') != std::string_view::npos)
    throw IoError("journal record contains a newline");
  const std::string line = hex8(crc32(record)) + " " + std::string(record) + "\n";
  if (!writeAll(fd_, line.data(), line.size()) || ::fdatasync(fd_) != 0) {
    const IoError error = systemError(path_, "cannot append to journal");
    // Leave no partial record behind; the next open would cut it anyway.
    if (::ftruncate(fd_, off_t(size_)) == 0) ::lseek(fd_, off_t(size_), SEEK_SET);
    throw error;
  }
  size_ += line.size();
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
  ReplacementFile file(path);
  writeSynced(file.writePath(), contents);
  file.commit();
  syncDirectory(path.parent_path());
}

void createFoldersDurably(const std::filesystem::path& folder) {
  if (folder.empty() || std::filesystem::is_directory(folder)) return;
  createFoldersDurably(folder.parent_path());
  if (::mkdir(folder.c_str(), 0755) != 0 && errno != EEXIST)
    throw systemError(folder, "cannot create folder");
  syncDirectory(folder.parent_path());
}

void discardFolderDurably(const std::filesystem::path& folder) {
  if (!std::filesystem::exists(folder)) return;
  const std::filesystem::path doomed = folder.string() + kDiscardedSuffix;
  std::error_code error;
  std::filesystem::remove_all(doomed, error);  // an earlier discard cut off
  if (::rename(folder.c_str(), doomed.c_str()) != 0)
    throw systemError(folder, "cannot discard (rename to " + doomed.filename().string() + ")");
  syncDirectory(folder.parent_path());
  std::filesystem::remove_all(doomed, error);
}

void moveFilesDurably(const std::vector<std::filesystem::path>& files,
                      const std::filesystem::path& folder) {
  if (files.empty()) return;
  createFoldersDurably(folder);
  std::vector<std::filesystem::path> sources;
  for (const std::filesystem::path& file : files) {
    const std::filesystem::path moved = folder / file.filename();
    if (::rename(file.c_str(), moved.c_str()) != 0)
      throw systemError(file, "cannot move into " + folder.string());
    if (std::find(sources.begin(), sources.end(), file.parent_path()) == sources.end())
      sources.push_back(file.parent_path());
  }
  syncDirectory(folder);
  for (const std::filesystem::path& source : sources) syncDirectory(source);
}

}  // namespace slicecap::io
