// Replacing a file through a temporary in its folder: rename(2) within one file system puts the
// new file in place in one step, so the old one survives every failure before it.
#include "slicecap/io/file_replacement.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <system_error>

#include "slicecap/io/io_error.hpp"

namespace slicecap::io {

namespace fs = std::filesystem;

ReplacementFile::ReplacementFile(fs::path target) : target_(std::move(target)) {
  std::error_code error;
  const fs::file_status status = fs::status(target_, error);
  if (fs::is_directory(status)) throw IoError(target_.string() + ": is a directory");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    writePath_ = replaced_ = target_;  // a device or a pipe: nothing to replace
    committed_ = true;
    return;
  }
  // Through a symbolic link, the file it names is replaced (renaming onto the link would turn
  // it into a plain file).
  replaced_ = fs::is_symlink(fs::symlink_status(target_, error)) && fs::exists(status)
                  ? fs::canonical(target_, error)
                  : target_;
  if (error) replaced_ = target_;
  writePath_ = replaced_;
  writePath_ += ".tmp";
}

ReplacementFile::~ReplacementFile() {
  if (committed_) return;
  std::error_code ignored;  // nothing to do about a temporary that cannot be removed
  fs::remove(writePath_, ignored);
}

void ReplacementFile::commit() {
  if (committed_) return;
  std::error_code error;
  fs::rename(writePath_, replaced_, error);
  if (error) throw IoError(target_.string() + ": cannot replace (" + error.message() + ")");
  committed_ = true;
}

void writeReplacing(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  ReplacementFile file(target);
  write(file.writePath());
  file.commit();
}

namespace {

// Writes `write`'s output to `writePath` and checks it reached the disk; errors name `target`.
void writeStreamTo(const fs::path& target, const fs::path& writePath,
                   const std::function<void(std::ostream&)>& write) {
  errno = 0;
  std::ofstream out(writePath, std::ios::binary | std::ios::trunc);
  if (!out)
    throw IoError(target.string() + ": cannot create" +
                  (errno ? std::string(" (") + std::strerror(errno) + ")" : std::string()));
  write(out);
  // A full disk may only show when the buffer is written out: at the flush or the close.
  out.flush();
  out.close();
  if (out.fail())
    throw IoError(target.string() + ": write failed (" +
                  (errno ? std::strerror(errno) : "disk full?") + ")");
}

}  // namespace

void writeStreamReplacing(const fs::path& target, const std::function<void(std::ostream&)>& write) {
  writeReplacing(target, [&](const fs::path& writePath) { writeStreamTo(target, writePath, write); });
}

void replaceFilesTogether(const std::vector<PendingFile>& files) {
  // Every temporary stays until all are written: a ReplacementFile not committed removes its own.
  std::vector<std::unique_ptr<ReplacementFile>> written;
  for (const PendingFile& file : files) {
    written.push_back(std::make_unique<ReplacementFile>(file.target));
    writeStreamTo(file.target, written.back()->writePath(),
                  [&](std::ostream& out) { out << file.contents; });
  }
  for (const std::unique_ptr<ReplacementFile>& file : written) file->commit();
}

}  // namespace slicecap::io
