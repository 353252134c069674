// Who may have slicecapd write an export where: its storage, or a folder the asking uid owns.
#include "export_authorization.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "slicecap/daemon/control_server.hpp"

namespace slicecap::daemon {

void authorizeExport(const control::Export& command, const std::optional<control::Peer>& peer,
                     const std::filesystem::path& storageRoot) {
  namespace fs = std::filesystem;
  if (command.directory.empty()) return;
  const fs::path wanted(command.directory);
  for (const fs::path& part : wanted)
    if (part == "..")
      throw RequestError(control::ErrorCode::BadRequest,
                         "export directory " + command.directory + " must not contain '..'");
  std::error_code error;
  fs::path existing = wanted;
  while (!fs::exists(existing, error) && existing.has_relative_path())
    existing = existing.parent_path();
  const fs::path real = fs::canonical(existing, error);
  if (error)
    throw RequestError(control::ErrorCode::BadRequest,
                       "export directory " + command.directory + ": " + error.message());
  const fs::path storage = fs::weakly_canonical(storageRoot, error);
  const auto [storageEnd, realEnd] =
      std::mismatch(storage.begin(), storage.end(), real.begin(), real.end());
  if (!error && storageEnd == storage.end()) return;  // the storage or a folder in it
  struct stat folder {};
  if (::stat(real.c_str(), &folder) != 0)
    throw RequestError(control::ErrorCode::BadRequest,
                       "export directory " + command.directory + ": " + std::strerror(errno));
  if (!peer)
    throw RequestError(
        control::ErrorCode::PermissionDenied,
        "export into " + command.directory + " refused: the daemon cannot tell who asked");
  if (peer->uid == 0 || folder.st_uid == peer->uid) return;
  throw RequestError(control::ErrorCode::PermissionDenied,
                     "export into " + command.directory + " refused: " + real.string() +
                         " belongs to uid " + std::to_string(folder.st_uid) + ", not to uid " +
                         std::to_string(peer->uid) +
                         " who asked (export into a folder you "
                         "own, or leave out the directory to export into the session's folder)");
}

}  // namespace slicecap::daemon
