// Who may have slicecapd write an export into a folder the client names.
#pragma once

#include <filesystem>
#include <optional>

#include "slicecap/control/protocol.hpp"

namespace slicecap::daemon {

/// \brief An export into a folder the client names is written with the daemon's rights: only into
/// its storage (`storageRoot`), or into a folder the asking uid owns (root may name any). The
/// nearest folder that exists, links resolved, decides: the export creates the rest inside it.
/// An empty directory (the session's own export folder) is always allowed. Throws RequestError:
/// bad_request for '..' or an unreadable path, permission_denied otherwise.
void authorizeExport(const control::Export& command, const std::optional<control::Peer>& peer,
                     const std::filesystem::path& storageRoot);

}  // namespace slicecap::daemon
