// A set of files replaced as one: written into a private folder beside them, synced, then swapped
// in by name with rename(2)s that a failure rolls back, the manifest last.
#include "slicecap/io/file_set.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>

#include "slicecap/io/io_error.hpp"
#include "slicecap/io/journal.hpp"

namespace slicecap::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

IoError systemError(const fs::path& path, const std::string& what, int error) {
  return IoError(path.string() + ": " + what + ": " + std::strerror(error));
}

// A descriptor closed with its owner.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// Names of the mechanism start with '.', so no member (a plain, visible name) meets them.
bool isMemberName(const std::string& name) {
  return !name.empty() && name.front() != '.' && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}

bool existsIn(int directory, const std::string& name) {
  struct stat status {};
  return ::fstatat(directory, name.c_str(), &status, AT_SYMLINK_NOFOLLOW) == 0;
}

// Syncs a written file or folder tree, following no link, so that after a power cut a name
// swapped in names complete contents.
void syncTree(const fs::path& path, const fs::path& shown) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ELOOP) return;  // a link a writer made: nothing of ours to sync
    throw systemError(shown, "cannot open to sync it", errno);
  }
  Descriptor file(fd);
  struct stat status {};
  if (::fstat(fd, &status) != 0) throw systemError(shown, "cannot sync", errno);
  if (S_ISDIR(status.st_mode))
    for (const fs::directory_entry& entry : fs::directory_iterator(path))
      syncTree(entry.path(), shown / entry.path().filename());
  if (::fsync(fd) != 0) throw systemError(shown, "cannot sync", errno);
}

std::vector<std::string> readMembers(int directory, const std::string& manifest) {
  const int fd = ::openat(directory, manifest.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return {};
  Descriptor file(fd);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return {};
    text.append(buffer, std::size_t(n));
  }
  std::vector<std::string> members;
  const json parsed = json::parse(text, nullptr, false);
  if (!parsed.is_object() || !parsed.contains("files") || !parsed["files"].is_array())
    return {};
  for (const json& name : parsed["files"])
    if (name.is_string() && isMemberName(name.get<std::string>()))
      members.push_back(name.get<std::string>());
  return members;
}

// One rename done while swapping, to be undone if a later one fails.
struct Move {
  int fromDirectory;
  std::string fromName;
  int toDirectory;
  std::string toName;
  bool exchanged;
};

class Swap {
 public:
  Swap(const fs::path& folder, int directory) : folder_(folder), directory_(directory) {}

  // Moves `name` from `from` to `to` (replacing nothing). IoError naming the folder's name.
  void move(int from, const std::string& fromName, int to, const std::string& toName) {
    if (::renameat(from, fromName.c_str(), to, toName.c_str()) != 0)
      throw systemError(folder_ / toName, "cannot move into place", errno);
    done_.push_back({from, fromName, to, toName, false});
  }

  // Puts the staged `name` in the folder's place of that name; what was there goes to
  // `previous` (by exchange where the file system can, else by two renames).
  void putInPlace(int staging, int previous, const std::string& name) {
    if (!existsIn(directory_, name)) {
      move(staging, name, directory_, name);
      return;
    }
    if (::renameat2(staging, name.c_str(), directory_, name.c_str(), RENAME_EXCHANGE) == 0) {
      done_.push_back({staging, name, directory_, name, true});
      return;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != EOPNOTSUPP)
      throw systemError(folder_ / name, "cannot replace", errno);
    move(directory_, name, previous, name);
    move(staging, name, directory_, name);
  }

  // Undoes every move, last first (best effort: a failure here has no better answer).
  void rollBack() noexcept {
    for (auto it = done_.rbegin(); it != done_.rend(); ++it) {
      if (it->exchanged)
        ::renameat2(it->fromDirectory, it->fromName.c_str(), it->toDirectory, it->toName.c_str(),
                    RENAME_EXCHANGE);
      else
        ::renameat(it->toDirectory, it->toName.c_str(), it->fromDirectory, it->fromName.c_str());
    }
    done_.clear();
  }

 private:
  fs::path folder_;
  int directory_;
  std::vector<Move> done_;
};

// Removes what a staging folder holds, then the folder (by name in `directory`).
void removeStaging(int directory, const std::string& name, const fs::path& shown) {
  std::error_code ignored;
  fs::remove_all(shown, ignored);  // does not follow links
  ::unlinkat(directory, name.c_str(), AT_REMOVEDIR);
}

// The entries' names: member names, not the manifest's, none twice. IoError naming
// the set and the name otherwise.
std::set<std::string> checkedNames(const std::string& set, const std::string& manifest,
                                   const std::vector<FileSetEntry>& entries) {
  std::set<std::string> names;
  for (const FileSetEntry& entry : entries)
    if (!isMemberName(entry.name) || entry.name == manifest || !names.insert(entry.name).second)
      throw IoError("file set " + set + ": bad or repeated name '" + entry.name +
                    "'");
  return names;
}

// A new, empty staging folder `stagingName` in `directoryFd`, opened: its descriptor. A staging
// folder an interrupted export left (it may hold the set before that export) goes; whatever
// stands at its name is replaced, not followed. IoError naming `staging`.
int createStaging(int directoryFd, const std::string& stagingName, const fs::path& staging) {
  if (existsIn(directoryFd, stagingName)) removeStaging(directoryFd, stagingName, staging);
  if (::mkdirat(directoryFd, stagingName.c_str(), 0700) != 0)
    throw systemError(staging, "cannot create", errno);
  const int stagingFd =
      ::openat(directoryFd, stagingName.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (stagingFd < 0) {
    const IoError error = systemError(staging, "cannot open", errno);
    ::unlinkat(directoryFd, stagingName.c_str(), AT_REMOVEDIR);
    throw error;
  }
  return stagingFd;
}

// Writes and syncs every entry under `base` (the staging folder, `staging` in messages): the
// paths they will have in `folder`. IoError naming the staging folder.
std::vector<fs::path> writeEntries(const std::vector<FileSetEntry>& entries, const fs::path& base,
                                   const fs::path& staging, const fs::path& folder) {
  std::vector<fs::path> placed;
  for (const FileSetEntry& entry : entries) {
    // Messages name the staging folder, not the descriptor's path.
    const auto named = [&](const std::string& what) {
      std::string message = what;
      for (std::size_t at = 0; (at = message.find(base.string(), at)) != std::string::npos;
           at += staging.string().size())
        message.replace(at, base.string().size(), staging.string());
      return IoError(message);
    };
    try {
      entry.write(base / entry.name);
      syncTree(base / entry.name, staging / entry.name);
    } catch (const IoError& error) {
      throw named(error.what());
    } catch (const fs::filesystem_error& error) {
      throw named(error.what());
    }
    placed.push_back(folder / entry.name);
  }
  return placed;
}

// The new manifest under `base`: the entries, then the previous set's members in `keep` that
// still exist. Returns the previous members that leave the set (stale). Throws what
// writeFileAtomically throws.
std::vector<std::string> writeManifest(int directoryFd, const std::string& manifest,
                                       const std::string& set,
                                       const std::vector<FileSetEntry>& entries,
                                       const std::set<std::string>& names,
                                       const std::vector<std::string>& keep, const fs::path& base) {
  const std::vector<std::string> previousMembers = readMembers(directoryFd, manifest);
  json listed = json::array();
  for (const FileSetEntry& entry : entries)
    listed.push_back(entry.name);
  std::vector<std::string> stale;
  for (const std::string& name : previousMembers) {
    if (names.count(name) || name == manifest) continue;
    if (std::find(keep.begin(), keep.end(), name) != keep.end()) {
      if (existsIn(directoryFd, name)) listed.push_back(name);
    } else {
      stale.push_back(name);
    }
  }
  writeFileAtomically(base / manifest,
                      json{{"format", 1}, {"set", set}, {"files", std::move(listed)}}.dump(1) +
                          "\n");
  return stale;
}

// The staging folder's `.previous`, where what the set replaces goes: its descriptor. IoError
// naming it.
int createPrevious(int stagingFd, const fs::path& staging) {
  const std::string previousName = ".previous";
  if (::mkdirat(stagingFd, previousName.c_str(), 0700) != 0)
    throw systemError(staging / previousName, "cannot create", errno);
  const int previousFd =
      ::openat(stagingFd, previousName.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (previousFd < 0) throw systemError(staging / previousName, "cannot open", errno);
  return previousFd;
}

// The swap itself, rolled back if any rename fails. IoError naming the file.
void swapIn(const fs::path& folder, int directoryFd, int stagingFd, int previousFd,
            const std::string& manifest, const std::vector<FileSetEntry>& entries,
            const std::vector<std::string>& stale) {
  Swap swap(folder, directoryFd);
  try {
    // The old manifest goes first: a crash in the swap leaves no manifest claiming a set.
    if (existsIn(directoryFd, manifest))
      swap.move(directoryFd, manifest, previousFd, manifest);
    for (const FileSetEntry& entry : entries)
      swap.putInPlace(stagingFd, previousFd, entry.name);
    for (const std::string& name : stale)
      if (existsIn(directoryFd, name)) swap.move(directoryFd, name, previousFd, name);
    swap.move(stagingFd, manifest, directoryFd, manifest);
  } catch (...) {
    swap.rollBack();
    throw;
  }
}

}  // namespace

std::string fileSetManifestName(const std::string& set) { return set + "-manifest.json"; }

std::vector<std::string> fileSetMembers(const fs::path& folder, const std::string& set) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return {};
  Descriptor directory(fd);
  return readMembers(fd, fileSetManifestName(set));
}

std::vector<fs::path> replaceFileSet(const fs::path& folder, const std::string& set,
                                     const std::vector<FileSetEntry>& entries,
                                     const std::vector<std::string>& keep) {
  const std::string manifest = fileSetManifestName(set);
  const std::set<std::string> names = checkedNames(set, manifest, entries);
  createFoldersDurably(folder);
  const int directoryFd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (directoryFd < 0) throw systemError(folder, "cannot open the folder", errno);
  const Descriptor directory(directoryFd);

  const std::string stagingName = "." + set + "-export.partial";
  const fs::path staging = folder / stagingName;
  const Descriptor stagingDirectory(createStaging(directoryFd, stagingName, staging));
  const int stagingFd = stagingDirectory.get();
  // Written through the descriptor: whoever can rename in `folder` cannot redirect the writes.
  const fs::path viaDescriptor = "/proc/self/fd/" + std::to_string(stagingFd);
  std::error_code procError;
  const fs::path base = fs::is_directory(viaDescriptor, procError) ? viaDescriptor : staging;
  std::vector<fs::path> placed;
  try {
    placed = writeEntries(entries, base, staging, folder);
    const std::vector<std::string> stale =
        writeManifest(directoryFd, manifest, set, entries, names, keep, base);
    const Descriptor previous(createPrevious(stagingFd, staging));
    if (::fsync(stagingFd) != 0) throw systemError(staging, "cannot sync", errno);
    swapIn(folder, directoryFd, stagingFd, previous.get(), manifest, entries, stale);
    if (::fsync(directoryFd) != 0) throw systemError(folder, "cannot sync", errno);
  } catch (...) {
    removeStaging(directoryFd, stagingName, staging);
    throw;
  }
  removeStaging(directoryFd, stagingName, staging);
  return placed;
}

}  // namespace slicecap::io
