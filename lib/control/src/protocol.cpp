// Request parsing and validation for the control protocol; never throws on client input.
#include "slicecap/control/protocol.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "slicecap/core/session_id.hpp"
#include "slicecap/core/error.hpp"
#include "slicecap/methods/method_id.hpp"

namespace slicecap::control {
namespace {

using nlohmann::json;

constexpr std::array<std::string_view, 12> kCommandNames{
    "hello",          "session.new",    "session.list", "session.show",
    "session.resume", "session.delete", "sweep.start",  "sweep.stop",
    "sweep.redo",     "status",         "reconstruct",  "export"};
constexpr std::size_t kMaxTextBytes = 256;

// Thrown only inside this file, turned into a ProtocolError at the boundary. A slicecap::Error all
// the same: were one ever to escape, a catch of std::exception (the server's last guard) still
// takes it instead of letting it end the daemon.
struct Refusal : Error {
  Refusal(ErrorCode refusalCode, const std::string& text) : Error(text), code(refusalCode) {}
  ErrorCode code;
};

// The C1 controls (U+0080-U+009F: a terminal takes U+009B as CSI) and the bidirectional
// embeddings, overrides and isolates (U+202A-U+202E, U+2066-U+2069: they reorder what a terminal
// shows after them), in UTF-8.
bool hasC1ControlOrBidiOverride(std::string_view s) {
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    const auto b0 = (unsigned char)s[i], b1 = (unsigned char)s[i + 1];
    if (b0 == 0xc2 && b1 >= 0x80 && b1 <= 0x9f) return true;
    if (b0 == 0xe2 && i + 2 < s.size()) {
      const auto b2 = (unsigned char)s[i + 2];
      if (b1 == 0x80 && b2 >= 0xaa && b2 <= 0xae) return true;
      if (b1 == 0x81 && b2 >= 0xa6 && b2 <= 0xa9) return true;
    }
  }
  return false;
}

const json& argument(const json& args, const char* name) {
  auto it = args.find(name);
  if (it == args.end())
    throw Refusal{ErrorCode::BadRequest, std::string("missing argument \"") + name + "\""};
  return *it;
}

std::string text(const json& args, const char* name) {
  const json& value = argument(args, name);
  if (!value.is_string())
    throw Refusal{ErrorCode::BadRequest, std::string("argument \"") + name + "\" must be a string"};
  std::string s = value.get<std::string>();
  if (s.empty() || s.size() > kMaxTextBytes) {
    throw Refusal{ErrorCode::BadRequest,
                  std::string("argument \"") + name + "\" must be 1 to 256 bytes"};
  }
  // A material name is printed back on an operator's terminal (`session list`): a newline would
  // forge a line there, an escape sequence would drive the terminal.
  if (std::any_of(s.begin(), s.end(),
                  [](char c) { return (unsigned char)c < 0x20 || c == 0x7f; }) ||
      hasC1ControlOrBidiOverride(s))
    throw Refusal{ErrorCode::BadRequest,
                  std::string("argument \"") + name +
                      "\" must not contain control characters or bidirectional overrides"};
  return s;
}

std::optional<std::string> optionalText(const json& args, const char* name) {
  if (!args.contains(name) || args[name].is_null()) return std::nullopt;
  return text(args, name);
}

std::string sessionId(const json& args, const char* name) {
  const json& value = argument(args, name);
  if (!value.is_string() || !isValidSessionId(value.get<std::string>())) {
    throw Refusal{ErrorCode::BadRequest,
                  std::string("argument \"") + name +
                      "\" must be 1-64 characters of a-z, 0-9, _ and -, starting with a letter "
                      "or digit"};
  }
  return value.get<std::string>();
}

// A reconstruction method's name: it becomes part of a file name (abrdf-<method>.exr) in the
// session's folder, so only a-z, 0-9 and '-'.
std::optional<std::string> optionalMethod(const json& args) {
  std::optional<std::string> method = optionalText(args, "method");
  if (method &&
      (method->size() > 32 ||
       method->find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") != std::string::npos))
    throw Refusal{ErrorCode::BadRequest,
                  "argument \"method\" must be 1-32 characters of a-z, 0-9 and -"};
  return method;
}

std::optional<std::string> optionalSessionId(const json& args, const char* name) {
  if (!args.contains(name) || args[name].is_null()) return std::nullopt;
  return sessionId(args, name);
}

int elevation(const json& args, const char* name) {
  const json& value = argument(args, name);
  if (!value.is_number())
    throw Refusal{ErrorCode::BadRequest, std::string("argument \"") + name + "\" must be a number"};
  const double deg = value.get<double>();
  const bool measured = std::any_of(kMeasuredElevationsDeg.begin(), kMeasuredElevationsDeg.end(),
                                    [&](int e) { return deg == e; });
  if (!measured) {
    throw Refusal{ErrorCode::BadRequest,
                  std::string("argument \"") + name + "\" must be 30 or 75 (deg)"};
  }
  return static_cast<int>(deg);
}

SliceId slice(const json& args) {
  const auto kind = parseSliceKind(text(args, "kind"));
  // A point slice is a kind of the offline formats, not a sweep the rig can make.
  if (!kind || *kind == SliceKind::Point)
    throw Refusal{ErrorCode::BadRequest, "argument \"kind\" must be \"axial\" or \"diagonal\""};
  return {*kind, {elevation(args, "theta_i"), elevation(args, "theta_v")}};
}

Command parseCommand(std::string_view name, const json& args) {
  if (name == "hello") return Hello{};
  if (name == "session.new")
    return SessionNew{text(args, "material"), optionalSessionId(args, "id")};
  if (name == "session.list") return SessionList{};
  if (name == "session.show") return SessionShow{sessionId(args, "id")};
  if (name == "session.resume") return SessionResume{sessionId(args, "id")};
  if (name == "session.delete") return SessionDelete{sessionId(args, "id")};
  if (name == "sweep.start") return SweepStart{slice(args)};
  if (name == "sweep.stop") return SweepStop{};
  if (name == "sweep.redo") return SweepRedo{slice(args)};
  if (name == "status") return Status{};
  if (name == "reconstruct") {
    return Reconstruct{optionalSessionId(args, "id"),
                       optionalMethod(args).value_or(methods::cliName(methods::MethodId::B))};
  }
  if (name == "export") {
    std::string directory = optionalText(args, "directory").value_or("");
    if (!directory.empty() && directory.front() != '/')
      throw Refusal{ErrorCode::BadRequest, "argument \"directory\" must be an absolute path"};
    return Export{optionalSessionId(args, "id"), std::move(directory), optionalMethod(args)};
  }
  throw Refusal{ErrorCode::BadRequest, "unknown command \"" + std::string(name) + "\""};
}

}  // namespace

std::string_view errorCodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::ParseError:
      return "parse_error";
    case ErrorCode::TooLarge:
      return "too_large";
    case ErrorCode::UnsupportedVersion:
      return "unsupported_version";
    case ErrorCode::BadRequest:
      return "bad_request";
    case ErrorCode::NotFound:
      return "not_found";
    case ErrorCode::Conflict:
      return "conflict";
    case ErrorCode::Unavailable:
      return "unavailable";
    case ErrorCode::StorageError:
      return "storage_error";
    case ErrorCode::PermissionDenied:
      return "permission_denied";
    case ErrorCode::Internal:
      return "internal";
  }
  return "internal";
}

std::string_view commandName(const Command& command) {
  return kCommandNames[command.index()];
}

std::variant<Request, ProtocolError> parseRequest(std::string_view line) {
  if (line.size() > kMaxRequestBytes) {
    return ProtocolError{ErrorCode::TooLarge,
                         "request longer than " + std::to_string(kMaxRequestBytes) + " bytes",
                         {}};
  }
  const json document = json::parse(line.begin(), line.end(), nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded() || !document.is_object()) {
    return ProtocolError{ErrorCode::ParseError, "a request is one JSON object on one line", {}};
  }
  std::optional<std::int64_t> id;
  if (auto it = document.find("id"); it != document.end() && it->is_number_integer())
    id = it->get<std::int64_t>();
  try {
    if (!id) throw Refusal{ErrorCode::BadRequest, "missing integer \"id\""};
    const auto v = document.find("v");
    if (v == document.end() || !v->is_number_integer())
      throw Refusal{ErrorCode::BadRequest, "missing integer \"v\""};
    if (v->get<std::int64_t>() != kProtocolVersion) {
      throw Refusal{ErrorCode::UnsupportedVersion,
                    "protocol version " + v->dump() + " is not supported (this daemon speaks 1)"};
    }
    const auto cmd = document.find("cmd");
    if (cmd == document.end() || !cmd->is_string())
      throw Refusal{ErrorCode::BadRequest, "missing string \"cmd\""};
    static const json kNoArguments = json::object();
    const auto args = document.find("args");
    if (args != document.end() && !args->is_object())
      throw Refusal{ErrorCode::BadRequest, "\"args\" must be an object"};
    return Request{*id, parseCommand(cmd->get_ref<const std::string&>(),
                                     args == document.end() ? kNoArguments : *args)};
  } catch (const Refusal& r) {
    return ProtocolError{r.code, r.what(), id};
  } catch (const json::exception& e) {
    return ProtocolError{ErrorCode::BadRequest, e.what(), id};
  }
}

std::string encodeRequest(const Request& request) {
  json args = json::object();
  std::visit(
      [&](const auto& c) {
        using T = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<T, SessionNew>) {
          args["material"] = c.material;
          if (c.id) args["id"] = *c.id;
        } else if constexpr (std::is_same_v<T, SessionShow> || std::is_same_v<T, SessionResume> ||
                             std::is_same_v<T, SessionDelete>) {
          args["id"] = c.id;
        } else if constexpr (std::is_same_v<T, SweepStart> || std::is_same_v<T, SweepRedo>) {
          args["kind"] = std::string(toString(c.slice.kind));
          args["theta_i"] = c.slice.elevations.thetaIDeg;
          args["theta_v"] = c.slice.elevations.thetaVDeg;
        } else if constexpr (std::is_same_v<T, Reconstruct>) {
          if (c.id) args["id"] = *c.id;
          args["method"] = c.method;
        } else if constexpr (std::is_same_v<T, Export>) {
          if (c.id) args["id"] = *c.id;
          if (!c.directory.empty()) args["directory"] = c.directory;
          if (c.method) args["method"] = *c.method;
        }
      },
      request.command);
  return json{{"v", kProtocolVersion},
              {"id", request.id},
              {"cmd", commandName(request.command)},
              {"args", args}}
      .dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string encodeResult(std::int64_t requestId, const nlohmann::json& result) {
  // Results may carry text a client sent (a material name); invalid UTF-8 must not throw here.
  return json{{"v", kProtocolVersion}, {"id", requestId}, {"ok", true}, {"result", result}}.dump(
      -1, ' ', false, json::error_handler_t::replace);
}

std::string encodeError(const ProtocolError& error) {
  json id = error.requestId ? json(*error.requestId) : json(nullptr);
  return json{{"v", kProtocolVersion},
              {"id", id},
              {"ok", false},
              {"error", {{"code", errorCodeName(error.code)}, {"message", error.message}}}}
      .dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace slicecap::control
