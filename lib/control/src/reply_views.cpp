// The replies' JSON, written and read here and, for the status's decoding check and tuning file,
// in decoding_views.cpp (docs/reference/protocol.md).
#include "slicecap/control/reply_views.hpp"

#include "decoding_views.hpp"
#include "reply_fields.hpp"

namespace slicecap::control {
namespace {

using nlohmann::json;
using reply_fields::field;
using reply_fields::optionalField;

std::vector<std::string> stringsOf(const json& object, const char* key) {
  return optionalField<std::vector<std::string>>(object, key).value_or(std::vector<std::string>{});
}

SliceId sliceFromJson(const json& object) {
  const auto kind = parseSliceKind(field<std::string>(object, "kind"));
  if (!kind) throw ReplyError("slicecapd's reply has an unknown slice kind: " + object.dump());
  return {*kind, {field<int>(object, "theta_i"), field<int>(object, "theta_v")}};
}

SliceProgress sliceProgressFromJson(const json& object) {
  return {sliceFromJson(object), field<std::size_t>(object, "samples"),
          field<int>(object, "bins_filled"),
          optionalField<std::size_t>(object, "samples_set_aside").value_or(0),
          optionalField<std::size_t>(object, "samples_refused"),
          optionalField<bool>(object, "damaged").value_or(false),
          optionalField<std::string>(object, "refused")};
}

JournalDamageView journalDamageFromJson(const json& object) {
  return {field<std::size_t>(object, "line"), field<std::string>(object, "message"),
          field<std::vector<std::string>>(object, "slices_set_aside"),
          field<std::size_t>(object, "samples_set_aside"),
          field<std::size_t>(object, "samples_lost")};
}

PassAgainView passAgainFromJson(const json& object) {
  return {sliceFromJson(field<json>(object, "slice")), field<double>(object, "azimuth_deg"),
          field<std::string>(object, "reason")};
}

CellTextureView cellTextureFromJson(const json& object) {
  return {sliceFromJson(field<json>(object, "slice")), field<std::string>(object, "action"),
          optionalField<double>(object, "spread_percent"), field<std::string>(object, "reason")};
}

}  // namespace

json sliceJson(const SliceId& slice) {
  return {{"name", toString(slice)},
          {"kind", std::string(toString(slice.kind))},
          {"theta_i", slice.elevations.thetaIDeg},
          {"theta_v", slice.elevations.thetaVDeg}};
}

json toJson(const SliceProgress& slice) {
  json entry = sliceJson(slice.slice);
  entry["samples"] = slice.samples;
  entry["bins_filled"] = slice.binsFilled;
  if (slice.samplesSetAside > 0) entry["samples_set_aside"] = slice.samplesSetAside;
  // Written with the count, 0 too: a reader then knows the daemon tells them apart.
  if (slice.samplesSetAside > 0) entry["samples_refused"] = slice.samplesRefused.value_or(0);
  if (slice.damaged) entry["damaged"] = true;
  if (slice.refused) entry["refused"] = *slice.refused;
  return entry;
}

json toJson(const JournalDamageView& damage) {
  return {{"line", damage.line},
          {"message", damage.message},
          {"slices_set_aside", damage.slicesSetAside},
          {"samples_set_aside", damage.samplesSetAside},
          {"samples_lost", damage.samplesLost}};
}

json toJson(const SessionView& session) {
  json slices = json::array();
  for (const SliceProgress& slice : session.slices)
    slices.push_back(toJson(slice));
  json object = {{"id", session.id},
                 {"material", session.material},
                 {"samples", session.samples},
                 {"slices", std::move(slices)}};
  if (session.createdUtc) object["created"] = *session.createdUtc;
  if (session.directory) object["directory"] = *session.directory;
  if (session.tornTailBytesDropped)
    object["torn_tail_bytes_dropped"] = *session.tornTailBytesDropped;
  if (!session.corruptJournalLines.empty())
    object["corrupt_journal_lines"] = session.corruptJournalLines;
  if (!session.journalDamage.empty()) {
    json damage = json::array();
    for (const JournalDamageView& d : session.journalDamage)
      damage.push_back(toJson(d));
    object["journal_damage"] = std::move(damage);
  }
  if (session.current) object["current"] = *session.current;
  return object;
}

SessionView sessionFromJson(const json& object) {
  SessionView session;
  session.id = field<std::string>(object, "id");
  session.material = field<std::string>(object, "material");
  session.samples = field<std::size_t>(object, "samples");
  if (object.contains("slices"))
    for (const json& slice : object.at("slices"))
      session.slices.push_back(sliceProgressFromJson(slice));
  session.createdUtc = optionalField<std::string>(object, "created");
  session.directory = optionalField<std::string>(object, "directory");
  session.tornTailBytesDropped = optionalField<std::size_t>(object, "torn_tail_bytes_dropped");
  session.corruptJournalLines =
      optionalField<std::vector<std::size_t>>(object, "corrupt_journal_lines")
          .value_or(std::vector<std::size_t>{});
  if (object.contains("journal_damage"))
    for (const json& damage : object.at("journal_damage"))
      session.journalDamage.push_back(journalDamageFromJson(damage));
  session.current = optionalField<bool>(object, "current");
  return session;
}

json toJson(const SweepView& sweep) {
  json rejected = json::object();
  for (const auto& [reason, count] : sweep.rejected)
    rejected[reason] = count;
  json object = {{"slice", sliceJson(sweep.slice)},
                 {"state", sweep.state},
                 {"bins", sweep.bins},
                 {"bins_filled", sweep.binsFilled},
                 {"samples", sweep.samples},
                 {"accepted_this_run", sweep.acceptedThisRun},
                 {"rejected", std::move(rejected)},
                 {"view_elevation_error_deg", nullptr}};
  if (sweep.pauseReason) object["pause_reason"] = *sweep.pauseReason;
  // Only an HDR sweep's highlight gives any: the key is there when there is one.
  if (!sweep.clippedBins.empty()) object["clipped_bins"] = sweep.clippedBins;
  if (sweep.viewElevationErrorDeg)
    object["view_elevation_error_deg"] = *sweep.viewElevationErrorDeg;
  return object;
}

SweepView sweepFromJson(const json& object) {
  SweepView sweep;
  sweep.slice = sliceFromJson(field<json>(object, "slice"));
  sweep.state = field<std::string>(object, "state");
  sweep.bins = field<std::vector<bool>>(object, "bins");
  sweep.binsFilled = field<int>(object, "bins_filled");
  // Absent from a daemon older than the field: none known.
  sweep.clippedBins =
      optionalField<std::vector<int>>(object, "clipped_bins").value_or(std::vector<int>{});
  sweep.samples = field<std::size_t>(object, "samples");
  sweep.acceptedThisRun = optionalField<std::size_t>(object, "accepted_this_run").value_or(0);
  sweep.rejected = optionalField<std::map<std::string, std::size_t>>(object, "rejected")
                       .value_or(std::map<std::string, std::size_t>{});
  sweep.viewElevationErrorDeg = optionalField<double>(object, "view_elevation_error_deg");
  sweep.pauseReason = optionalField<std::string>(object, "pause_reason");
  return sweep;
}

json toJson(const IsotropyView& isotropy) {
  if (isotropy.error)
    return {{"error", *isotropy.error}, {"axial_sweeps_needed", isotropy.axialSweepsNeeded}};
  return {{"isotropic", isotropy.isotropic ? json(*isotropy.isotropic) : json(nullptr)},
          {"informative", isotropy.informative},
          {"axial_sweeps_needed", isotropy.axialSweepsNeeded},
          {"reason", isotropy.reason}};
}

IsotropyView isotropyFromJson(const json& object) {
  IsotropyView isotropy;
  isotropy.axialSweepsNeeded = field<bool>(object, "axial_sweeps_needed");
  isotropy.error = optionalField<std::string>(object, "error");
  if (isotropy.error) return isotropy;
  isotropy.isotropic = optionalField<bool>(object, "isotropic");
  isotropy.informative = field<bool>(object, "informative");
  isotropy.reason = field<std::string>(object, "reason");
  return isotropy;
}

json toJson(const RecordingView& recording) {
  json object = {{"directory", recording.directory},
                 {"frames_written", recording.framesWritten},
                 {"frames_queued", recording.framesQueued},
                 {"frames_dropped", recording.framesDropped}};
  if (recording.error) object["error"] = *recording.error;
  return object;
}

RecordingView recordingFromJson(const json& object) {
  return {field<std::string>(object, "directory"), field<std::size_t>(object, "frames_written"),
          field<std::size_t>(object, "frames_queued"),
          field<std::size_t>(object, "frames_dropped"),
          optionalField<std::string>(object, "error")};
}

json toJson(const TextureProgressView& texture) {
  json object = {{"directory", texture.directory},
                 {"resolution", texture.resolution},
                 {"bins_filled", texture.binsFilled},
                 {"frames_stored", texture.framesStored}};
  if (texture.sessionFramesStored) object["session_frames_stored"] = *texture.sessionFramesStored;
  if (texture.storedMb) object["stored_mb"] = *texture.storedMb;
  if (texture.damagedFramesRemoved) object["damaged_frames_removed"] = *texture.damagedFramesRemoved;
  return object;
}

TextureProgressView textureProgressFromJson(const json& object) {
  TextureProgressView texture;
  texture.resolution = field<int>(object, "resolution");
  texture.binsFilled = field<int>(object, "bins_filled");
  texture.framesStored = field<std::size_t>(object, "frames_stored");
  texture.directory = field<std::string>(object, "directory");
  texture.sessionFramesStored = optionalField<std::size_t>(object, "session_frames_stored");
  texture.storedMb = optionalField<double>(object, "stored_mb");
  texture.damagedFramesRemoved = optionalField<std::size_t>(object, "damaged_frames_removed");
  return texture;
}

namespace {

json toJson(const CameraFramesView& frames) {
  return {{"delivered", frames.delivered},
          {"dropped", frames.dropped},
          {"led_pattern", frames.ledPattern},
          {"led_clean_fraction", frames.ledCleanFraction},
          {"timing", frames.timing}};
}

CameraFramesView cameraFramesFromJson(const json& object) {
  return {field<std::uint64_t>(object, "delivered"), field<std::uint64_t>(object, "dropped"),
          field<std::string>(object, "led_pattern"), field<double>(object, "led_clean_fraction"),
          field<std::string>(object, "timing")};
}

json toJson(const RoomLightView& room) {
  json object = json::object();
  if (room.toLed) object["to_led"] = *room.toLed;
  if (room.change) object["change"] = *room.change;
  if (room.changeToLed) object["change_to_led"] = *room.changeToLed;
  return object;
}

RoomLightView roomLightFromJson(const json& object) {
  return {optionalField<double>(object, "to_led"), optionalField<double>(object, "change"),
          optionalField<double>(object, "change_to_led")};
}

}  // namespace

json toJson(const StatusView& status) {
  json object = {{"session", status.session ? toJson(*status.session) : json(nullptr)},
                 {"sweep", status.sweep ? toJson(*status.sweep) : json(nullptr)},
                 {"next", status.next}};
  if (status.isotropy) object["isotropy"] = toJson(*status.isotropy);
  if (!status.passAgain.empty()) {
    json bins = json::array();
    for (const PassAgainView& bin : status.passAgain)
      bins.push_back({{"slice", sliceJson(bin.slice)},
                      {"azimuth_deg", bin.azimuthDeg},
                      {"reason", bin.reason}});
    object["pass_again"] = std::move(bins);
  }
  for (const CellTextureView& cells : status.cellTextures)
    object["cell_texture"].push_back(
        {{"slice", sliceJson(cells.slice)},
         {"action", cells.action},
         {"spread_percent", cells.spreadPercent ? json(*cells.spreadPercent) : json(nullptr)},
         {"reason", cells.reason}});
  if (status.error) object["error"] = *status.error;
  if (status.recording) object["recording"] = toJson(*status.recording);
  if (status.texture) object["texture"] = toJson(*status.texture);
  if (status.exposure) object["exposure"] = *status.exposure;
  if (status.hdr) object["hdr"] = *status.hdr;
  if (status.cameraFrames) object["camera_frames"] = toJson(*status.cameraFrames);
  if (status.decoding)
    object["decoding"] = {{"decoding", status.decoding->decoding}, {"note", status.decoding->note}};
  // Written once a figure is known: a room light without any is left out.
  if (status.roomLight && !toJson(*status.roomLight).empty())
    object["room_light"] = toJson(*status.roomLight);
  if (status.decodingCheck && !toJson(*status.decodingCheck).empty())
    object["decoding_check"] = toJson(*status.decodingCheck);
  if (status.tuningFile) object["tuning_file"] = toJson(*status.tuningFile);
  if (!status.warnings.empty()) object["warnings"] = status.warnings;
  return object;
}

StatusView statusFromJson(const json& object) {
  StatusView status;
  if (const auto session = optionalField<json>(object, "session"))
    status.session = sessionFromJson(*session);
  if (const auto sweep = optionalField<json>(object, "sweep")) status.sweep = sweepFromJson(*sweep);
  status.next = field<std::string>(object, "next");
  if (const auto isotropy = optionalField<json>(object, "isotropy"))
    status.isotropy = isotropyFromJson(*isotropy);
  // Optional: a daemon from before it does not send it.
  for (const json& bin : optionalField<json>(object, "pass_again").value_or(json::array()))
    status.passAgain.push_back(passAgainFromJson(bin));
  for (const json& cells : optionalField<json>(object, "cell_texture").value_or(json::array()))
    status.cellTextures.push_back(cellTextureFromJson(cells));
  status.error = optionalField<std::string>(object, "error");
  if (const auto recording = optionalField<json>(object, "recording"))
    status.recording = recordingFromJson(*recording);
  if (const auto texture = optionalField<json>(object, "texture"))
    status.texture = textureProgressFromJson(*texture);
  status.exposure = optionalField<std::string>(object, "exposure");
  status.hdr = optionalField<std::string>(object, "hdr");
  if (const auto frames = optionalField<json>(object, "camera_frames"))
    status.cameraFrames = cameraFramesFromJson(*frames);
  if (const auto decoding = optionalField<json>(object, "decoding"))
    status.decoding = DecodingView{field<std::string>(*decoding, "decoding"),
                                   field<std::string>(*decoding, "note")};
  if (const auto room = optionalField<json>(object, "room_light"))
    status.roomLight = roomLightFromJson(*room);
  if (const auto check = optionalField<json>(object, "decoding_check"))
    status.decodingCheck = decodingCheckFromJson(*check);
  if (const auto tuning = optionalField<json>(object, "tuning_file"))
    status.tuningFile = tuningFileFromJson(*tuning);
  status.warnings = stringsOf(object, "warnings");
  return status;
}

json toJson(const SweepStopView& stop) {
  json object = toJson(stop.sweep);
  if (stop.recording) object["recording"] = toJson(*stop.recording);
  if (stop.texture) object["texture"] = toJson(*stop.texture);
  return object;
}

json toJson(const SessionListEntry& entry) {
  json object = {{"id", entry.id},
                 {"material", entry.material},
                 {"created", entry.createdUtc},
                 {"current", entry.current}};
  if (entry.damaged) object["damaged"] = *entry.damaged;
  return object;
}

std::vector<SessionListEntry> sessionListFromJson(const json& object) {
  std::vector<SessionListEntry> sessions;
  for (const json& entry : field<json>(object, "sessions"))
    sessions.push_back({field<std::string>(entry, "id"), field<std::string>(entry, "material"),
                        field<std::string>(entry, "created"), field<bool>(entry, "current"),
                        optionalField<std::string>(entry, "damaged")});
  return sessions;
}

json toJson(const ExportView& reply) {
  json object = {{"session", reply.session},
                 {"directory", reply.directory},
                 {"files", reply.files},
                 {"method", reply.method}};
  if (reply.material) object["material"] = *reply.material;
  if (!reply.warnings.empty()) object["warnings"] = reply.warnings;
  if (reply.texture) {
    object["texture"] = *reply.texture;
    object["texture_files"] = reply.textureFiles;
  }
  if (reply.textureSkipped) object["texture_skipped"] = *reply.textureSkipped;
  return object;
}

ExportView exportFromJson(const json& object) {
  ExportView reply;
  reply.session = field<std::string>(object, "session");
  reply.directory = field<std::string>(object, "directory");
  reply.files = field<std::vector<std::string>>(object, "files");
  reply.method = field<std::string>(object, "method");
  reply.material = optionalField<std::string>(object, "material");
  reply.warnings = stringsOf(object, "warnings");
  reply.texture = optionalField<std::string>(object, "texture");
  if (reply.texture) reply.textureFiles = field<std::vector<std::string>>(object, "texture_files");
  reply.textureSkipped = optionalField<std::string>(object, "texture_skipped");
  return reply;
}

}  // namespace slicecap::control
