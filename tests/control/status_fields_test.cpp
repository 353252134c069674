// The status reply's documented keys (statusFields: `slicecap status --help`, the protocol
// reference) are exactly the keys toJson(StatusView) writes when every field is set: a new field
// without a line, or a line for a key no longer written, fails here.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "slicecap/control/reply_views.hpp"

namespace slicecap::control {
namespace {

using nlohmann::json;

// Every field of the status set, each optional figure too.
StatusView everyField() {
  StatusView status;
  status.session = SessionView{};
  status.sweep = SweepView{};
  status.next = "next";
  status.isotropy = IsotropyView{};
  status.passAgain = {PassAgainView{{SliceKind::Diagonal, {75, 75}}, 90.0, "peak_not_reached"}};
  status.cellTextures = {CellTextureView{{SliceKind::Diagonal, {75, 75}}, "window centres", 64.0,
                                         "reason"}};
  status.error = "error";
  status.recording = RecordingView{"dir", 1, 2, 3, "stopped"};
  TextureProgressView texture;
  texture.sessionFramesStored = 1;
  texture.storedMb = 0.5;
  texture.damagedFramesRemoved = 0;
  status.texture = texture;
  status.exposure = "exposure";
  status.hdr = "hdr";
  status.cameraFrames = CameraFramesView{};
  status.decoding = DecodingView{"srgb", "note"};
  status.roomLight = RoomLightView{0.1, 0.2, 0.02};
  status.decodingCheck =
      DecodingCheckView{1.02, 0.01, 2.0, "G", 0.5, "G", 0.6, 0.1, 3.0, 2.5, "kept", "R", 0.01, 5.0};
  status.tuningFile = TuningFileView{"auto", "/usr/share/slicecap/tuning/x.json", "processed path"};
  status.warnings = {"warning"};
  return status;
}

TEST(StatusFields, AreExactlyTheKeysTheStatusWrites) {
  std::set<std::string> documented, parents;
  for (const ReplyField& field : statusFields()) {
    EXPECT_TRUE(documented.insert(field.key).second) << field.key << " is documented twice";
    EXPECT_FALSE(field.meaning.empty()) << field.key;
    if (const auto dot = field.key.find('.'); dot != std::string::npos)
      parents.insert(field.key.substr(0, dot));
  }
  // The keys written: each top-level key, and inside the objects whose keys are documented
  // one by one (for a list of objects, its entries), each of theirs.
  const json status = toJson(everyField());
  std::set<std::string> written;
  for (const auto& [key, value] : status.items()) {
    written.insert(key);
    if (!parents.count(key)) continue;
    const json& inside = value.is_array() && !value.empty() ? value.front() : value;
    for (const auto& [inner, ignored] : inside.items()) written.insert(key + "." + inner);
  }
  EXPECT_EQ(documented, written);
}

// window_unlit is a figure: whether it refuses the sweep depends on the stream, the setting and
// the samples, which window_unlit_verdict says in each case (its values:
// DecodingWatch.SaysWhatTheRuleMakesOfTheRunInEachCase), so the figure's text claims no refusal.
TEST(StatusFields, TheUnlitFigureClaimsNoRefusalAndItsVerdictNamesEachCase) {
  std::map<std::string, std::string> meaning;
  for (const ReplyField& field : statusFields()) meaning[field.key] = field.meaning;
  for (const char* figure : {"decoding_check.window_unlit", "decoding_check.window_unlit_channel",
                             "decoding_check.window_unlit_at_zero"})
    EXPECT_EQ(meaning.at(figure).find("refused"), std::string::npos) << figure;
  const std::string& verdict = meaning.at("decoding_check.window_unlit_verdict");
  for (const char* whenNot :
       {"RAW", "fewer than 4 samples", "refuse_broken_decoding = false", "no session was open",
        "the run ended"})
    EXPECT_NE(verdict.find(whenNot), std::string::npos) << whenNot;
}

}  // namespace
}  // namespace slicecap::control
