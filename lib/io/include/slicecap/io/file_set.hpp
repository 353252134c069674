// Replacing a set of files in a folder as one (an export): the folder holds the whole old set or
// the whole new one, never a mix, and no link planted in it is written through.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace slicecap::io {

/// \brief One member of a file set: its name in the folder and how to make it.
struct FileSetEntry {
  std::string name;  ///< a plain file name (no '/', not "." or ".."), unique in the set
  /// Writes the whole file (or folder) at `writePath`, throwing on any failure.
  std::function<void(const std::filesystem::path& writePath)> write;
};

/// \brief The manifest that lists a set's members in its folder: `<set>-manifest.json`. It is
/// put in place last, so a folder with the manifest holds the complete set it lists.
std::string fileSetManifestName(const std::string& set);

/// \brief Replaces the set `set` in `folder` (created if missing) with `entries`, as one:
/// every entry is written into a fresh folder `.<set>-export.partial` inside `folder` (same
/// file system; mode 0700, made for this call) and synced; only when all are complete are they
/// swapped in by name (renameat2 RENAME_EXCHANGE, so a failed swap is rolled back), the names
/// the previous manifest listed and this set does not make (other than `keep`) moved out, and
/// the new manifest put in place last; then the folder is synced. A failure before the swap
/// (a full disk, a writer that throws) leaves `folder` as it was; what the writer threw passes
/// through, other failures are IoError naming the file.
///
/// Nothing in `folder` is opened or followed: a name is replaced by renaming over it, so a
/// symbolic link planted there is replaced, never written through; and only names listed in
/// this set's own previous manifest are ever removed. Returns the entries' paths in `folder`.
std::vector<std::filesystem::path> replaceFileSet(const std::filesystem::path& folder,
                                                  const std::string& set,
                                                  const std::vector<FileSetEntry>& entries,
                                                  const std::vector<std::string>& keep = {});

/// \brief The names the manifest of `set` in `folder` lists (empty when there is none or it
/// cannot be read).
std::vector<std::string> fileSetMembers(const std::filesystem::path& folder,
                                        const std::string& set);

}  // namespace slicecap::io
