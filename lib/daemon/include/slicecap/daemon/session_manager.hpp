// The daemon's sessions and sweeps: what each control command does, what the frame loop reports,
// and the status a person watches. Independent of cameras and of how frames become samples.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>

#include "slicecap/capture/reject_reason.hpp"
#include "slicecap/capture/session_store.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/core/abrdf.hpp"
#include "slicecap/control/protocol.hpp"
#include "slicecap/daemon/session_exporter.hpp"

namespace slicecap::daemon {

/// \brief The isotropy test's answer on a session's slices: are the axial sweeps needed?
struct IsotropyAssessment {
  bool isotropic = true;
  /// \brief false when the slices cannot show anisotropy (e.g. only the equal-elevation diagonal
  /// ones); "isotropic" is then a default, not a finding.
  bool informative = true;
  std::string reason;  ///< one sentence for the operator
};
/// \brief Runs the isotropy test (prior::testIsotropy; injected, like the reconstruction, by the
/// daemon's main). Throws std::exception with a message (e.g. no prior file).
using IsotropyFunction = std::function<IsotropyAssessment(const SliceSet& slices)>;

/// \brief The state machine behind the control protocol. One session is current at a time; at
/// most one sweep runs. Every change is durable (SessionStore) before the command's reply. The
/// current session's id is kept in <storage>/current, so a restarted daemon comes back to it; a
/// sweep that was running when the daemon died comes back paused ("interrupted"), with every
/// acknowledged sample, and `sweep.start` of the same slice continues it.
class SessionManager {
 public:
  /// \brief Opens the storage root (creating it) and the session that was current. Throws
  /// io::IoError naming the folder if it cannot be used. Without `isotropy`, status never says
  /// whether the axial sweeps can be skipped. Without `material`, exports hold no fitted material.
  SessionManager(std::filesystem::path storageRoot, ReconstructFunction reconstruct,
                 PreviewFunction preview = {}, IsotropyFunction isotropy = {},
                 MaterialFunction material = {});
  ~SessionManager();

  /// \brief Carries out one command. Never throws: refusals and failures come back as a
  /// ProtocolError with a message for the person at the other end.
  std::variant<nlohmann::json, control::ProtocolError> handle(const control::Command& command);

  /// \brief True while a sweep runs and is not paused: the frame loop wants frames and strobes
  /// the LED; otherwise the LED stays off.
  bool capturing() const;
  /// \brief The slice being swept (running or paused).
  std::optional<SliceId> sweepSlice() const;
  /// \brief The current session's folder (where record_frames keeps its recordings).
  std::optional<std::filesystem::path> sessionDirectory() const;

  /// \brief Stores a frame's sample durably. If the store cannot write (disk full), the sweep
  /// stops with a storage error in its status and this returns false; nothing stored is lost.
  bool acceptSample(const capture::FrameSample& sample);
  /// \brief Counts a rejected frame under its reason ("too_few_markers", "elevation_off", ...).
  void rejectFrame(capture::RejectReason reason);
  /// \brief The view elevation's distance from the slice's nominal in the last posed frame, shown
  /// live so the person can correct the arm.
  void noteViewElevationErrorDeg(double errorDeg);
  /// \brief The camera or LED failed: the sweep pauses (samples kept) with the reason shown.
  void pauseSweep(const std::string& reason);
  /// \brief The current session's next journal record number (SessionStore::nextRecordNumber):
  /// where a sweep run beginning now starts. None without a session.
  std::optional<std::uint64_t> nextRecordNumber() const;
  /// \brief A sweep run of `slice` whose decoding was shown broken (DecodingWatch::refusal): the
  /// current session sets the run's samples aside (those from journal record `firstRecord` on,
  /// capture::SessionStore::refuse: kept in its journal, used by no table or export) and the
  /// status's error (after the pause's reason, if the run ended in a pause) and the slice say
  /// why. `textureFrames`: the run's texture frames, recorded with the refusal so that opening
  /// the session sets them aside again (refusals()). A storage failure is logged and shown as
  /// the error; the samples then still count, and this returns false.
  bool refuseSweep(const SliceId& slice, const std::string& reason, std::uint64_t firstRecord,
                   std::optional<capture::RunTextureFrames> textureFrames = std::nullopt);
  /// \brief The current session's refusals since each slice's last redo (none without a session).
  std::vector<capture::SweepRefusal> refusals() const;
  /// \brief A sentence added to the status's error, after what it says (a refusal's texture
  /// frames); nothing for an empty one.
  void addToError(const std::string& sentence);

  /// \brief The sweep (running or paused), as its replies show it.
  std::optional<control::SweepView> sweepView() const;

  /// \brief The session manager's part of the status: session, sweep, isotropy, error, next
  /// (the daemon's sweep devices add theirs).
  control::StatusView statusView() const;
  /// \brief toJson(statusView()): the reply to the status command of a daemon without devices.
  nlohmann::json status() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// \brief A SessionManager reply as a ControlServer handler returns it: the JSON, or a thrown
/// RequestError carrying the refusal's code and message.
nlohmann::json replyOrThrow(std::variant<nlohmann::json, control::ProtocolError> reply);

/// \brief The eight slices in the order a person sweeps them: the diagonal ones first, equal
/// elevations first (30/30, 75/75, 30/75, 75/30), then the axial ones (30/30, 30/75, 75/30,
/// 75/75). Someone who knows the material is isotropic may stop after two; after all four
/// diagonal ones the isotropy test says whether the axial ones are needed.
const std::vector<SliceId>& sweepOrder();

}  // namespace slicecap::daemon
