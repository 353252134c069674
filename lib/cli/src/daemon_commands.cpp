// The commands a person on SSH uses to drive slicecapd: session, sweep, status, export. Each sends
// protocol commands over the control socket and prints the answer for a person, or as JSON.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <system_error>
#include <thread>

#include "slicecap/cli/cli.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/control/control_client.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/methods/method_id.hpp"
#include "slicecap/io/file_set.hpp"
#include "slicecap/io/io_error.hpp"
#include "reply_text.hpp"

namespace slicecap::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kDefaultSocket = "/run/slicecap/slicecapd.sock";

const OptionSpec kSocketOption{
    "socket", 0, "PATH",
    "slicecapd's control socket (default $SLICECAP_SOCKET or " + std::string(kDefaultSocket) + ")"};
const OptionSpec kJsonOption{"json", 0, "",
                             "print the daemon's answer as JSON (an error too: {\"error\": ...})"};

fs::path socketPath(const ParsedArgs& args) {
  if (auto given = args.value("socket")) return *given;
  if (const char* env = std::getenv("SLICECAP_SOCKET"); env != nullptr && *env != '\0') return env;
  return kDefaultSocket;
}

/// Sends one command; a refusal becomes an exception carrying the daemon's message (exit 1).
json call(const ParsedArgs& args, const control::Command& command) {
  control::ControlClient client(socketPath(args));
  return client.call(command);
}

SliceId sliceFrom(const ParsedArgs& args, std::size_t first) {
  const auto kind = parseSliceKind(args.positional.at(first));
  if (!kind)
    throw UsageError("slice kind '" + args.positional[first] + "' is not axial or diagonal");
  auto elevation = [&](std::size_t i, const char* name) {
    const std::string& text = args.positional.at(i);
    if (text != "30" && text != "75")
      throw UsageError(std::string(name) + " '" + text + "' must be 30 or 75 (deg)");
    return std::stoi(text);
  };
  return {*kind, {elevation(first + 1, "THETA_I"), elevation(first + 2, "THETA_V")}};
}

int finish(const ParsedArgs& args, Streams& io, const json& result,
           const std::function<void(std::ostream&, const json&)>& print) {
  if (args.flag("json"))
    io.out << result.dump(2) << "\n";
  else
    print(io.out, result);
  return kExitOk;
}

void printSessionList(std::ostream& out, const json& reply) {
  const std::vector<control::SessionListEntry> sessions = control::sessionListFromJson(reply);
  if (sessions.empty()) out << "no sessions\n";
  for (const control::SessionListEntry& session : sessions) {
    out << (session.current ? "* " : "  ") << session.id;
    if (session.damaged)
      out << "  damaged: " << *session.damaged << "\n";
    else
      out << "  " << session.createdUtc << "  " << session.material << "\n";
  }
}

int runSession(const ParsedArgs& args, Streams& io) {
  const std::string& action = args.positional[0];
  auto needs = [&](std::size_t count, const char* synopsis) {
    if (args.positional.size() != count + 1)
      throw UsageError("session " + action + ": usage: slicecap session " + action + " " +
                       synopsis);
  };
  if (action == "new") {
    needs(1, "MATERIAL [--id ID]");
    return finish(args, io, call(args, control::SessionNew{args.positional[1], args.value("id")}),
                  printSessionReply);
  }
  if (action == "list") {
    needs(0, "");
    return finish(args, io, call(args, control::SessionList{}),
                  printSessionList);
  }
  if (action == "show") {
    needs(1, "ID");
    return finish(args, io, call(args, control::SessionShow{args.positional[1]}),
                  printSessionReply);
  }
  if (action == "resume") {
    needs(1, "ID");
    return finish(args, io, call(args, control::SessionResume{args.positional[1]}),
                  printSessionReply);
  }
  if (action == "delete") {
    needs(1, "ID");
    return finish(args, io, call(args, control::SessionDelete{args.positional[1]}),
                  [](std::ostream& out, const json& r) {
                    out << "deleted " << r["deleted"].get<std::string>() << "\n";
                  });
  }
  throw UsageError("session: unknown action '" + action + "' (new, list, show, resume, delete)");
}

void printSweep(std::ostream& out, const json& reply) {
  const control::SweepView sweep = control::sweepFromJson(reply);
  out << "sweep " << toString(sweep.slice) << ": " << sweep.state << ", " << sweep.samples
      << " samples, bins " << bar(sweep.bins) << " " << sweep.binsFilled << "/"
      << control::kBinsPerSlice << "\n";
  if (!sweep.clippedBins.empty()) out << "  " << clippedBinsLine(sweep) << "\n";
  if (sweep.pauseReason) out << "  " << *sweep.pauseReason << "\n";
}

int runSweep(const ParsedArgs& args, Streams& io) {
  const std::string& action = args.positional[0];
  if (action == "stop") {
    if (args.positional.size() != 1) throw UsageError("sweep stop takes no arguments");
    return finish(args, io, call(args, control::SweepStop{}), printSweep);
  }
  if (action == "start" || action == "redo") {
    if (args.positional.size() != 4)
      throw UsageError("sweep " + action + ": usage: slicecap sweep " + action +
                       " axial|diagonal THETA_I THETA_V");
    const SliceId slice = sliceFrom(args, 1);
    const control::Command command =
        action == "start" ? control::Command{control::SweepStart{slice}}
                          : control::Command{control::SweepRedo{slice}};
    const json reply = call(args, command);
    // The daemon takes the command, but a camera, exposure lock or texture store that fails at
    // once leaves the sweep paused with the reason: it is not capturing, so this is no success
    // (a script's `sweep start ... && ...` went on as if it were).
    if (const control::SweepView sweep = control::sweepFromJson(reply); sweep.state == "paused")
      throw control::DaemonError(
          std::string(control::errorCodeName(control::ErrorCode::Unavailable)),
          "sweep " + toString(sweep.slice) + " is paused, not capturing: " +
              sweep.pauseReason.value_or("no reason given"));
    return finish(args, io, reply, printSweep);
  }
  throw UsageError("sweep: unknown action '" + action + "' (start, stop, redo)");
}

volatile std::sig_atomic_t interrupted = 0;

int runStatus(const ParsedArgs& args, Streams& io) {
  if (!args.flag("watch")) return finish(args, io, call(args, control::Status{}), printStatus);
  const double intervalSeconds = args.number("interval", 0.5);
  if (intervalSeconds < 0.05) throw UsageError("--interval must be at least 0.05 s");
  const double count = args.number("count", 0);
  if (args.value("count") && !(count >= 1 && count <= 1e9 && count == std::floor(count)))
    throw UsageError("--count must be a whole number from 1 to 1000000000");
  interrupted = 0;
  auto previous = std::signal(SIGINT, [](int) { interrupted = 1; });
  control::ControlClient client(socketPath(args));
  for (long shown = 0; !interrupted && (count <= 0 || shown < long(count)); ++shown) {
    const json status = client.call(control::Status{});
    if (args.flag("json")) {
      io.out << status.dump() << "\n";
    } else {
      io.out << "\x1b[H\x1b[2J";  // home and clear: one screen that updates in place
      printStatus(io.out, status);
      io.out << "(Ctrl-C to stop watching; the sweep goes on)\n";
    }
    io.out.flush();
    std::this_thread::sleep_for(std::chrono::duration<double>(intervalSeconds));
  }
  std::signal(SIGINT, previous);
  return kExitOk;
}

// One file of the box's export, copied into the set's new version at `copy`.
void copyExportedFile(const fs::path& source, const fs::path& copy) {
  std::error_code error;
  fs::create_directories(copy.parent_path(), error);
  if (!error) fs::copy_file(source, copy, fs::copy_options::overwrite_existing, error);
  if (error)
    throw io::IoError("cannot copy " + source.string() + " to " + copy.string() + ": " +
                      error.message());
}

// The session's texture folder into `copy`: exactly the files the reply lists (the daemon's
// exporter chose them; it can be hundreds of MB, so it is copied from the box's folder, not
// duplicated there).
void copyTexture(const control::ExportView& reply, const fs::path& copy) {
  std::error_code error;
  fs::create_directories(copy, error);
  if (error) throw io::IoError(copy.string() + ": cannot create: " + error.message());
  for (const std::string& file : reply.textureFiles)
    copyExportedFile(fs::path(*reply.texture) / file, copy / file);
}

// Fetches what the daemon exported into DIR as one set (io::replaceFileSet, as the daemon's own
// export folder): exactly the files the reply lists. A failed copy leaves DIR's previous export
// whole, no link planted in DIR is written through, and only files this session's earlier export
// listed in its manifest go.
int runExport(const ParsedArgs& args, Streams& io) {
  const fs::path destination = args.required("output");
  std::optional<std::string> method = args.value("method");
  if (method) method = methods::cliName(methods::methodNamed(*method));  // unknown: exit 2
  const control::ExportView reply =
      control::exportFromJson(call(args, control::Export{args.positional[0], "", method}));
  std::vector<io::FileSetEntry> entries;
  for (const std::string& file : reply.files) {
    const fs::path source = file;
    entries.push_back({source.filename().string(),
                       [source](const fs::path& copy) { copyExportedFile(source, copy); }});
  }
  const std::string textureName = reply.session + "-texture";
  if (reply.texture)
    entries.push_back(
        {textureName, [&reply](const fs::path& copy) { copyTexture(reply, copy); }});
  // A texture not exported this time (a sweep was capturing into it): the earlier copy stays.
  std::vector<std::string> keep;
  if (reply.textureSkipped) keep.push_back(textureName);
  json copied = json::array();
  for (const fs::path& path : io::replaceFileSet(destination, reply.session, entries, keep))
    copied.push_back(path.string());
  for (const std::string& warning : reply.warnings)
    io.err << "warning: " << warning << "\n";
  if (reply.textureSkipped)
    io.err << "warning: texture not exported: " << *reply.textureSkipped << "\n";
  json answer = {{"session", reply.session}, {"method", reply.method}, {"files", copied}};
  if (reply.material) answer["material"] = *reply.material;
  return finish(args, io, answer, [](std::ostream& out, const json& r) {
    out << "exported session " << r["session"].get<std::string>() << " (reconstructed with "
        << r["method"].get<std::string>() << "):\n";
    for (const json& f : r["files"])
      out << "  " << f.get<std::string>() << "\n";
    if (r.contains("material")) out << "material: " << r["material"].get<std::string>() << "\n";
  });
}

// With --json a script reads stdout: an error is there too, as one line {"error": MESSAGE} (and
// "code", the protocol's error code, when the daemon refused), besides the text on stderr and the
// exit code, which the caller's boundary (runCli) still gives.
std::function<int(const ParsedArgs&, Streams&)> withJsonErrors(int (*run)(const ParsedArgs&,
                                                                          Streams&)) {
  return [run](const ParsedArgs& args, Streams& io) {
    try {
      return run(args, io);
    } catch (const std::exception& e) {
      if (args.flag("json")) {
        json error = {{"error", e.what()}};
        if (const auto* refusal = dynamic_cast<const control::DaemonError*>(&e))
          error["code"] = refusal->code();
        // Replacing bytes that are not UTF-8 (a path may hold any): dump must not throw here.
        io.out << error.dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
      }
      throw;
    }
  };
}

}  // namespace

Command sessionCommand() {
  return {
      {"session",
       "new MATERIAL [--id ID] | list | show ID | resume ID | delete ID [--socket PATH] [--json]",
       "Manage capture sessions on slicecapd: start one for a material, list them, show one "
       "with\nits slices, make an earlier one current again, or delete one.",
       {{"id", 0, "ID", "session new: the session's id (1-64 of a-z 0-9 _ -; default s<UTC time>)"},
        kSocketOption,
        kJsonOption},
       1,
       2},
      withJsonErrors(runSession)};
}

Command sweepCommand() {
  return {{"sweep",
           "start|redo axial|diagonal THETA_I THETA_V | stop [--socket PATH] [--json]",
           "Start, stop or redo the sweep of one slice of the current session. THETA_I and "
           "THETA_V are\nthe light and view elevations, 30 or 75 deg. `sweep start` of a paused "
           "sweep continues it;\n`redo` discards the slice's samples and sweeps it again. A start "
           "or redo that the camera\n(or texture store) leaves paused at once exits with 1 and "
           "the reason.",
           {kSocketOption, kJsonOption},
           1,
           4},
          withJsonErrors(runSweep)};
}

Command statusCommand() {
  return {{"status",
           "[--watch [--interval S] [--count N]] [--socket PATH] [--json]",
           "What slicecapd is doing: the current session and its slices, the sweep's bins as a "
           "bar of 24\ncells, the view elevation error now, rejected frames by reason, the "
           "camera's frames, exposure,\ndecoding and room light, and what to do next. --watch "
           "redraws it until Ctrl-C.\n\n" + statusFieldsText(),
           {{"watch", 'w', "", "redraw continuously"},
            {"interval", 0, "S", "seconds between redraws (default 0.5)"},
            {"count", 0, "N", "stop after N redraws (default: until Ctrl-C)"},
            kSocketOption,
            kJsonOption},
           0,
           0},
          withJsonErrors(runStatus)};
}

Command exportCommand() {
  return {{"export",
           "SESSION -o DIR [--method NAME] [--socket PATH] [--json]",
           "Export a session from slicecapd into DIR: its ABRDF as EXR, reconstructed now from "
           "the samples\nas they are (Method B when all eight slices have samples, else the "
           "learned prior fitted to\nevery window cell, prior-cells, which reads any subset: e.g. "
           "the diagonal sweeps of an\nisotropic material; --method picks another), and any "
           "table made earlier, made afresh;\na PNG preview of each, the slices CSV and a JSON "
           "summary; with texture capture on\n"
           "(texture_resolution), also DIR/SESSION-texture: the texture's frames and the slices,\n"
           "for `slicecap btf DIR/SESSION-texture -o BTF`.",
           {{"output", 'o', "DIR", "the folder to copy the files into (required)"},
            {"method", 0, "NAME",
             "the reconstruction method (b, b-cells, prior-cells, prior, a, halfway, ...)"},
            kSocketOption,
            kJsonOption},
           1,
           1},
          withJsonErrors(runExport)};
}

}  // namespace slicecap::cli
