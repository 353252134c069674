// The daemon's replies: the session manager's answer with the sweep devices' part.
#include "daemon_replies.hpp"

#include "export_authorization.hpp"
#include "slicecap/daemon/control_server.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::daemon {
namespace {

using nlohmann::json;
using control::ErrorCode;

// A redone sweep's texture starts afresh, as its samples: discarded before the redo is journaled.
void discardTexture(const control::SweepRedo& redo, SweepDevices& devices) {
  try {
    devices.outputs().discardTexture(redo.slice);
  } catch (const io::IoError& error) {
    throw RequestError(control::ErrorCode::StorageError, std::string("cannot discard the old sweep's texture: ") +
                                                    error.what() + " (nothing was redone)");
  }
}

}  // namespace

json replyOrThrow(std::variant<json, control::ProtocolError> reply) {
  if (auto* error = std::get_if<control::ProtocolError>(&reply))
    throw RequestError(error->code, error->message);
  return std::move(std::get<json>(reply));
}

namespace {

// The session manager's reply to a command; a refusal leaves the devices in line before it goes.
nlohmann::json managerReply(const control::Command& command, SessionManager& manager,
                            SweepDevices& devices) {
  try {
    if (const auto* redo = std::get_if<control::SweepRedo>(&command)) discardTexture(*redo, devices);
    // A stop settles the LED-on frames still waiting for their LED-off frame first, as the
    // stream's end does: their samples belong to the sweep being stopped.
    if (std::holds_alternative<control::SweepStop>(command) && manager.capturing())
      devices.settleHeld();
    return replyOrThrow(manager.handle(command));
  } catch (const RequestError&) {
    devices.reconcile();
    throw;
  }
}

}  // namespace

nlohmann::json answer(const control::Request& request, SessionManager& manager, SweepDevices& devices,
                      const std::filesystem::path& storage) {
  const control::Command& command = request.command;
  if (const auto* exporting = std::get_if<control::Export>(&command))
    authorizeExport(*exporting, request.peer, storage);
  if (std::holds_alternative<control::Status>(command)) {
    control::StatusView status = manager.statusView();
    devices.describe(status);
    devices.reconcile();
    return control::toJson(status);
  }
  nlohmann::json reply = managerReply(command, manager, devices);
  if (const auto* redo = std::get_if<control::SweepRedo>(&command))
    devices.outputs().discardRecording(redo->slice);
  // The recording of a sweep being stopped is reported in the stop's reply.
  if (std::holds_alternative<control::SweepStop>(command))
    reply = control::toJson(control::SweepStopView{control::sweepFromJson(reply),
                                                   devices.outputs().recordingView(),
                                                   devices.outputs().textureView()});
  devices.reconcile();
  // A start the devices refused at once (camera, texture) comes back paused, with the reason.
  if ((std::holds_alternative<control::SweepStart>(command) ||
       std::holds_alternative<control::SweepRedo>(command)) &&
      manager.sweepSlice() && !manager.capturing())
    reply = control::toJson(*manager.sweepView());
  return reply;
}

}  // namespace slicecap::daemon
