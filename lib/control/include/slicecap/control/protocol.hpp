// The control protocol between `slicecap` and `slicecapd`: one JSON object a line, versioned.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "slicecap/core/slice.hpp"
#include "slicecap/methods/method_id.hpp"

namespace slicecap::control {

/// \brief The protocol version this build speaks; requests carry it as "v".
inline constexpr int kProtocolVersion = 1;
/// \brief Longest request line accepted, in bytes (without the newline); longer ones get
/// `too_large`.
inline constexpr std::size_t kMaxRequestBytes = 64 * 1024;

/// \brief Why a request was refused; the wire spelling is errorCodeName().
enum class ErrorCode {
  ParseError,          ///< not JSON, or not an object
  TooLarge,            ///< longer than kMaxRequestBytes
  UnsupportedVersion,  ///< "v" is not kProtocolVersion
  BadRequest,          ///< unknown command, missing or invalid argument
  NotFound,            ///< no such session
  Conflict,            ///< not possible in the current state (e.g. a sweep already running)
  Unavailable,         ///< the camera or LED failed; the sweep is paused
  StorageError,        ///< the store could not write (e.g. disk full); nothing was acknowledged
  PermissionDenied,    ///< the client may not do this (e.g. export into another user's folder)
  Internal,            ///< a bug: reported, the daemon stays up
};
std::string_view errorCodeName(ErrorCode code);

// The commands. Each holds exactly the validated arguments it needs.
struct Hello {};
struct SessionNew {
  std::string material;           ///< free text, what the person is capturing
  std::optional<std::string> id;  ///< a chosen session id (else the daemon makes one)
};
struct SessionList {};
struct SessionShow {
  std::string id;
};
struct SessionResume {
  std::string id;
};
struct SessionDelete {
  std::string id;
};
struct SweepStart {
  SliceId slice;
};
struct SweepStop {};
struct SweepRedo {
  SliceId slice;  ///< discards that slice's samples and starts it again
};
struct Status {};
struct Reconstruct {
  std::optional<std::string> id;  ///< default: the current session
  /// A method of the registry (`slicecap reconstruct --help`); on the wire 1-32 characters of
  /// a-z, 0-9 and '-' (it names <session>/abrdf-<method>.exr), else a bad_request reply.
  std::string method = methods::cliName(methods::MethodId::B);
};
struct Export {
  std::optional<std::string> id;  ///< default: the current session
  /// Absolute path on the box; empty: the session's own `export/` folder, which the daemon can
  /// always write (its unit allows writes to its state folder only) and `slicecap export` copies
  /// from. The reply lists the files written; with a texture it also names the session's texture
  /// folder ("texture"), which is not copied (it can be hundreds of MB): the client copies it.
  std::string directory;
  /// The method of the session's table (named as Reconstruct's); default: defaultExportMethod().
  /// Every table is made afresh from the samples as they are now, so no export carries a table
  /// from before a later sweep or redo.
  std::optional<std::string> method;
};

using Command =
    std::variant<Hello, SessionNew, SessionList, SessionShow, SessionResume, SessionDelete,
                 SweepStart, SweepStop, SweepRedo, Status, Reconstruct, Export>;

/// \brief The wire name of a command ("session.new", ...).
std::string_view commandName(const Command& command);

/// \brief Who sent a request: the socket's peer credentials (SO_PEERCRED) at connect time.
struct Peer {
  std::int64_t pid = 0;
  std::uint32_t uid = 0;
  std::uint32_t gid = 0;
};

/// \brief A parsed, validated request.
struct Request {
  std::int64_t id = 0;  ///< chosen by the client, echoed in the response
  Command command;
  /// Set by the server from the connection, never read from the wire; empty: unknown (then
  /// nothing that depends on who asks is allowed).
  std::optional<Peer> peer{};
};

/// \brief A refusal: the code, a message naming the field, and the request id if one was readable.
struct ProtocolError {
  ErrorCode code = ErrorCode::BadRequest;
  std::string message;
  std::optional<std::int64_t> requestId;
};

/// \brief Parses one request line (without its newline). Never throws: any input, however malformed
/// or large, gives either a Request or a ProtocolError.
std::variant<Request, ProtocolError> parseRequest(std::string_view line);

/// \brief The request line for a command (the client side), without the newline.
std::string encodeRequest(const Request& request);

/// \brief A success response line: {"v":1,"id":ID,"ok":true,"result":RESULT}.
std::string encodeResult(std::int64_t requestId, const nlohmann::json& result);
/// \brief An error response line: {"v":1,"id":ID|null,"ok":false,"error":{"code":...,
/// "message":...}}.
std::string encodeError(const ProtocolError& error);

}  // namespace slicecap::control
