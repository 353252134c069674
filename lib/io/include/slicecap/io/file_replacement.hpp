// Writing a file so that a failed write never costs the file it replaces: through a temporary in
// the same folder, renamed onto the target only once the whole write has succeeded.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace slicecap::io {

/// \brief The temporary file that replaces a target when committed: `<target>.tmp` in the target's
/// folder (the folder of the file a symbolic link names, so the link stays a link). commit()
/// renames it onto the target; until then the target is untouched, and the destructor removes
/// the temporary if it was not committed, whatever went wrong (disk full, an exception).
/// A target that exists but is not a regular file (a device or a pipe, e.g. /dev/stdout) cannot
/// be replaced: it is written in place.
class ReplacementFile {
 public:
  /// \brief Creates nothing yet. Throws IoError naming `target` when it is a directory.
  explicit ReplacementFile(std::filesystem::path target);
  ~ReplacementFile();
  ReplacementFile(const ReplacementFile&) = delete;
  ReplacementFile& operator=(const ReplacementFile&) = delete;

  /// \brief The path as given, for messages.
  const std::filesystem::path& target() const { return target_; }
  /// \brief Where to write: the temporary (or the target itself when it is written in place).
  const std::filesystem::path& writePath() const { return writePath_; }
  /// \brief Puts the written file in the target's place. Throws IoError naming the target when
  /// the rename fails (the temporary is then removed).
  void commit();

 private:
  std::filesystem::path target_, replaced_, writePath_;
  bool committed_ = false;
};

/// \brief Writes `target` through a ReplacementFile: `write` is given the path to write (the
/// temporary) and must write the whole file there and throw on any failure; only when it returns
/// is the file put in the target's place. Whatever `write` throws passes through, the target
/// untouched and the temporary removed. Throws IoError naming the target for a directory or a
/// failed rename.
void writeReplacing(const std::filesystem::path& target,
                    const std::function<void(const std::filesystem::path& writePath)>& write);

/// \brief writeReplacing for a stream: `write` fills a binary std::ofstream on the temporary,
/// which is then flushed and closed and checked, so that a failed write (disk full) is an
/// IoError naming the target ("write failed") and never a truncated file in its place. Also
/// IoError naming the target when it cannot be created; what `write` throws passes through.
void writeStreamReplacing(const std::filesystem::path& target,
                          const std::function<void(std::ostream& out)>& write);

/// \brief One file of replaceFilesTogether: where it goes and its whole contents.
struct PendingFile {
  std::filesystem::path target;
  std::string contents;
};

/// \brief Replaces several files as one command's outputs (a fitted material and its exports,
/// which may lie in different folders): every file is written to its own temporary
/// (ReplacementFile) first, and only when all are written are they put in place, in order. A
/// failure while writing (a full disk, a folder that does not exist, a target that is a
/// directory) leaves every target as it was and no temporary behind. A rename failing after others
/// succeeded, which needs the folder itself to change under us, leaves the earlier ones replaced.
/// A target that is a device is written in place when its turn comes in the writing step. Throws
/// IoError naming the target.
void replaceFilesTogether(const std::vector<PendingFile>& files);

}  // namespace slicecap::io
