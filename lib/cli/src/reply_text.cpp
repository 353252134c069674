// The daemon's replies as a person reads them: a session's slices, a sweep's bins, the status
// (`slicecap session`, `sweep`, `status`), and the status's fields for `slicecap status --help`.
#include "reply_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace slicecap::cli {

using nlohmann::json;

std::string bar(const std::vector<bool>& bins) {
  std::string text = "[";
  for (const bool filled : bins)
    text += filled ? '#' : '.';
  return text + "]";
}


namespace {

std::string padded(std::string text, std::size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text;
}

// Why a slice's samples were set aside, from the counts (a redo forgets a refusal's reason, not
// which samples it set aside); a daemon before the counts were told apart says only the reason.
std::string setAsideText(const control::SliceProgress& slice) {
  const std::size_t refused =
      slice.samplesRefused.value_or(slice.refused ? slice.samplesSetAside : 0);
  const std::size_t damage = slice.samplesSetAside - std::min(refused, slice.samplesSetAside);
  const std::string total = std::to_string(slice.samplesSetAside) + " set aside (";
  if (damage == 0) return total + "sweep refused)";
  if (refused == 0) return total + "damaged journal)";
  return total + std::to_string(refused) + " sweep refused, " + std::to_string(damage) +
         " damaged journal)";
}

void printSession(std::ostream& out, const control::SessionView& session) {
  out << "session " << session.id << " (" << session.material << "), " << session.samples
      << " samples";
  if (session.createdUtc) out << ", created " << *session.createdUtc;
  out << "\n";
  for (const control::SliceProgress& slice : session.slices) {
    out << "  " << padded(toString(slice.slice), 16) << slice.binsFilled << "/"
        << control::kBinsPerSlice << " bins, " << slice.samples << " samples";
    if (slice.samplesSetAside > 0) out << ", " << setAsideText(slice);
    out << "\n";
    // A refused sweep's reason names what to change: never only in --json.
    if (slice.refused) out << "    refused: " << *slice.refused << "\n";
  }
  // What the journal could not tell for sure, each naming the file and line: never only in --json.
  for (const control::JournalDamageView& damage : session.journalDamage)
    out << "journal damage: " << damage.message << "\n";
}

std::string isotropyText(const control::IsotropyView& isotropy) {
  if (isotropy.error) return *isotropy.error;
  return std::string(isotropy.isotropic == false ? "anisotropic, the axial sweeps are needed"
                     : isotropy.axialSweepsNeeded
                         ? "cannot tell yet, the axial sweeps are needed"
                         : "isotropic, the axial sweeps are not needed") +
         " (" + isotropy.reason + ")";
}

void printSweepProgress(std::ostream& out, const control::SweepView& sweep) {
  out << "sweep " << toString(sweep.slice) << ": " << sweep.state << "\n"
      << "  bins " << bar(sweep.bins) << " " << sweep.binsFilled << "/" << control::kBinsPerSlice
      << "\n";
  if (!sweep.clippedBins.empty()) out << "  " << clippedBinsLine(sweep) << "\n";
  if (sweep.viewElevationErrorDeg) {
    char text[32];
    std::snprintf(text, sizeof text, "%+.1f", *sweep.viewElevationErrorDeg);
    out << "  view elevation error " << text << " deg\n";
  }
  if (!sweep.rejected.empty()) {
    out << "  rejected frames:";
    for (const auto& [reason, count] : sweep.rejected)
      out << " " << reason << " " << count;
    out << "\n";
  }
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", 100.0 * fraction);
  return text;
}

// What the strobe counted of a live camera's frames: a camera that drops frames, or an LED whose
// switches land in the rows read, costs samples.
std::string cameraFramesLine(const control::CameraFramesView& frames) {
  return "camera: " + std::to_string(frames.delivered) + " frames, " +
         std::to_string(frames.dropped) + " dropped, LED " + frames.ledPattern + ", " +
         percent(frames.ledCleanFraction) + " with one LED state over the rows read (" +
         frames.timing + ")";
}

std::string roomLightLine(const control::RoomLightView& room) {
  std::string line = "room light:";
  if (room.toLed) line += " " + percent(*room.toLed) + " of the LED's light";
  if (room.changeToLed)
    line += std::string(room.toLed ? "," : "") + " changing by " + percent(*room.changeToLed) +
            " of it between LED-off frames";
  return line;
}

std::string decodingCheckLine(const control::DecodingCheckView& check) {
  char figure[64];
  std::string line = "decoding check:";
  if (check.blackReading) {
    std::snprintf(figure, sizeof figure, " black patch reads %.3f of its albedo", *check.blackReading);
    line += figure;
  }
  if (check.blackReadingStep) {
    std::snprintf(figure, sizeof figure, " (%.1f standard errors)",
                  check.blackReadingStepSigmas.value_or(0.0));
    line += std::string(check.blackReading ? "," : "") + " stepping " +
            percent(*check.blackReadingStep) + " from a frame to the next" + figure;
  }
  if (check.windowAtBlack && check.windowAtBlackChannel)
    line += std::string(check.blackReading || check.blackReadingStep ? "," : "") + " window " +
            *check.windowAtBlackChannel + " " + percent(*check.windowAtBlack) + " at code 0";
  if (check.windowUnlit && check.windowUnlitChannel) {
    line += std::string(line.back() == ':' ? "" : ",") + " window " + *check.windowUnlitChannel +
            " unlit by the LED in " + percent(*check.windowUnlit) + " of the samples";
    if (check.windowUnlitSigmas) {
      std::snprintf(figure, sizeof figure, " (median %+.1f", *check.windowUnlitSigmas);
      line += figure;
      if (check.windowUnlitMeanSigmas) {
        std::snprintf(figure, sizeof figure, ", mean %+.1f", *check.windowUnlitMeanSigmas);
        line += figure;
      }
      line += " standard errors from 0)";
    }
    if (check.windowUnlitVerdict) line += " - " + *check.windowUnlitVerdict;
  }
  if (check.windowStep && check.windowStepChannel) {
    std::snprintf(figure, sizeof figure, " (%.1f standard errors)",
                  check.windowStepSigmas.value_or(0.0));
    line += std::string(line.back() == ':' ? "" : ",") + " window " + *check.windowStepChannel +
            " stepping " + percent(*check.windowStep) + " from a frame to the next" + figure;
  }
  return line;
}

std::string tuningFileLine(const control::TuningFileView& tuning) {
  return "tuning file: " + (tuning.file ? *tuning.file : std::string("the camera's own")) +
         " (tuning_file = " + tuning.setting + (tuning.reason.empty() ? "" : ": " + tuning.reason) +
         ")";
}

}  // namespace

void printSessionReply(std::ostream& out, const json& reply) {
  printSession(out, control::sessionFromJson(reply));
}

// An HDR sweep's bins whose highlight clipped at every exposure, by their slice parameter.
std::string clippedBinsLine(const control::SweepView& sweep) {
  std::string line = "clipped at every exposure, a lower bound (sweep over them again slower):";
  const double widthDeg = 360.0 / control::kBinsPerSlice;
  for (const int bin : sweep.clippedBins) line += " " + std::to_string(int(std::lround(bin * widthDeg))) + " deg";
  return line;
}

void printStatus(std::ostream& out, const json& reply) {
  const control::StatusView status = control::statusFromJson(reply);
  if (!status.session)
    out << "no current session\n";
  else
    printSession(out, *status.session);
  if (status.sweep) printSweepProgress(out, *status.sweep);
  if (status.recording)
    out << "  raw frames recorded: " << status.recording->framesWritten << " in "
        << status.recording->directory << ", " << status.recording->framesDropped
        << " dropped from the recording (writer behind)\n";
  if (status.recording && status.recording->error) out << "  " << *status.recording->error << "\n";
  if (status.texture)
    out << "  texture " << status.texture->resolution << " x " << status.texture->resolution
        << ": " << status.texture->binsFilled << "/" << control::kBinsPerSlice << " bins, "
        << status.texture->framesStored << " frames kept in " << status.texture->directory
        << "\n";
  // The bins to pass again, one line a slice: "pass again slowly, diagonal 75/75: 90 deg (peak
  // not reached), 210 deg (empty)".
  for (std::size_t k = 0; k < status.passAgain.size();) {
    const SliceId slice = status.passAgain[k].slice;
    out << "pass again slowly, " << toString(slice) << ":";
    for (const char* separator = " "; k < status.passAgain.size() &&
                                      status.passAgain[k].slice == slice;
         ++k, separator = ", ")
      out << separator << std::lround(status.passAgain[k].azimuthDeg) << " deg ("
          << (status.passAgain[k].reason == "empty" ? "empty" : "peak not reached") << ")";
    out << "\n";
  }
  // A finished sweep whose window cells are not read as they are (texture): what its export's
  // cell slices and bins to pass again read instead, and why. Plain sweeps say nothing.
  for (const control::CellTextureView& cells : status.cellTextures)
    if (cells.action != "as read")
      out << "cells, " << toString(cells.slice) << ": " << cells.action << " (" << cells.reason
          << ")\n";
  if (status.isotropy) out << "isotropy: " << isotropyText(*status.isotropy) << "\n";
  if (status.error) out << "error: " << *status.error << "\n";
  if (status.exposure) out << "exposure: " << *status.exposure << "\n";
  if (status.hdr) out << "hdr: " << *status.hdr << "\n";
  if (status.decoding)
    out << "decoding: " << status.decoding->decoding << " (" << status.decoding->note << ")\n";
  if (status.cameraFrames) out << cameraFramesLine(*status.cameraFrames) << "\n";
  if (status.roomLight) out << roomLightLine(*status.roomLight) << "\n";
  if (status.decodingCheck) out << decodingCheckLine(*status.decodingCheck) << "\n";
  if (status.tuningFile) out << tuningFileLine(*status.tuningFile) << "\n";
  for (const std::string& warning : status.warnings)
    out << "warning: " << warning << "\n";
  out << "next: " << status.next << "\n";
}

std::string statusFieldsText() {
  // The key's column, and the meaning wrapped at about 100 columns under its own start.
  constexpr std::size_t kKeyWidth = 36, kLineWidth = 100;
  std::string text = "The status reply's fields (--json; docs/reference/protocol.md):\n";
  for (const control::ReplyField& field : control::statusFields()) {
    std::string line = "  " + field.key;
    line.append(line.size() < kKeyWidth ? kKeyWidth - line.size() : 1, ' ');
    std::size_t start = 0;
    while (start < field.meaning.size()) {
      std::size_t end = field.meaning.size();
      if (line.size() + (end - start) > kLineWidth) {
        end = field.meaning.rfind(' ', start + (kLineWidth - line.size()));
        if (end == std::string::npos || end <= start) end = field.meaning.find(' ', start);
        if (end == std::string::npos) end = field.meaning.size();
      }
      text += line + field.meaning.substr(start, end - start) + "\n";
      start = end < field.meaning.size() ? end + 1 : end;
      line = std::string(kKeyWidth, ' ');
    }
  }
  text.pop_back();  // the help adds its own line end
  return text;
}

}  // namespace slicecap::cli
