// Durable storage: an append-only record journal (fsync per record) and atomic whole-file
// replacement.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace slicecap::io {

/// \brief What opening a journal found and repaired.
struct JournalRecovery {
  std::size_t records = 0;  ///< intact records read
  std::size_t tornTailBytes =
      0;  ///< bytes of an unfinished last record (a crash mid-append), cut off
  std::vector<std::size_t> corruptLines;  ///< 1-based lines whose checksum failed; skipped
};

/// \brief One line of a journal as read back: its record when the checksum holds, else what is
/// left of it (for its reader to judge what the damaged record may have been).
struct JournalLine {
  std::size_t line = 0;  ///< 1-based line number in the file
  std::string text;      ///< the record (checksum and space removed when well formed)
  bool intact = false;   ///< the checksum matches
};

/// \brief Where Journal::open keeps the bytes of a torn tail it cuts off: `<journal>.torn`
/// (appended to, so nothing that was on disk is deleted).
std::filesystem::path tornTailFile(const std::filesystem::path& journal);

/// \brief An append-only file of records, one a line as "<crc32 hex8> <record>\n". append() returns
/// only when the record is on disk (fdatasync), so an acknowledged record survives kill -9 and
/// power loss; a record torn by a crash is cut off when the journal is next opened.
class Journal {
 public:
  /// \brief Opens or creates the journal; fills `records` with the intact records in order. Throws
  /// IoError naming the path when it cannot be opened, read or repaired.
  static Journal open(const std::filesystem::path& path, std::vector<std::string>* records,
                      JournalRecovery* recovery = nullptr);
  /// \brief As open, but gives every line, damaged ones too, with its line number: a reader
  /// that must not skip some records (a state change) judges the damaged ones itself. A torn
  /// tail is cut off and its bytes appended to tornTailFile(path) first.
  static Journal openLines(const std::filesystem::path& path, std::vector<JournalLine>* lines,
                           JournalRecovery* recovery = nullptr);

  Journal(Journal&& other) noexcept;
  Journal& operator=(Journal&& other) noexcept;
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;
  ~Journal();

  /// \brief Appends one record (it may not contain a newline: IoError) and syncs it.
  /// Throws IoError naming the path when the write or sync fails (e.g. disk full); the journal is
  /// then cut back to its previous length, so every record before stays valid.
  void append(std::string_view record);

  const std::filesystem::path& path() const { return path_; }

 private:
  Journal(std::filesystem::path path, int fd, std::uint64_t size);
  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// \brief Replaces `path` with `contents` atomically (a temporary in the same folder, fsync,
/// rename, fsync of the folder): readers see the old file or the new one, never a mix. Throws
/// IoError.
void writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

/// \brief Creates `folder` and its missing parents, each new one synced in its parent, so that a
/// file then written atomically inside survives a power cut with the folder. Throws IoError.
void createFoldersDurably(const std::filesystem::path& folder);

/// \brief The suffix a folder being deleted carries (discardFolderDurably): readers skip such a
/// folder and its owner removes what is left of it.
inline constexpr const char* kDiscardedSuffix = ".discarded";

/// \brief Deletes a folder tree so that a crash cannot leave part of it looking valid: renamed to
/// `<folder>.discarded` first (atomic, synced in the parent), then removed. Nothing happens if it
/// does not exist. Throws IoError if it cannot be renamed; a failed removal after the rename is
/// left to the owner's next clean-up.
void discardFolderDurably(const std::filesystem::path& folder);

/// \brief The suffix of a folder whose files were set aside (a refused sweep run's texture
/// frames): kept on disk, read by no store, left out of every export.
inline constexpr const char* kSetAsideSuffix = ".set-aside";

/// \brief The suffix of a folder holding files an unjudged sweep run replaced (frames of earlier
/// runs a texture bin no longer keeps): put back if the run is refused, deleted if it is kept;
/// read by no store, left out of every export.
inline constexpr const char* kHeldSuffix = ".held";

/// \brief Moves each of `files` into `folder` (created durably if missing) under its own name, so
/// that after a power cut each is in one of the two places: renamed, then both folders synced.
/// The files must be on the folder's file system. Throws IoError naming the file that could not
/// be moved (those before it are moved).
void moveFilesDurably(const std::vector<std::filesystem::path>& files,
                      const std::filesystem::path& folder);

/// \brief CRC-32 (IEEE 802.3, as zlib) of bytes.
std::uint32_t crc32(std::string_view bytes);

}  // namespace slicecap::io
