// The replies of slicecapd as typed values: the daemon makes their JSON and the CLI reads it here,
// in one place (docs/reference/protocol.md gives the fields).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/core/error.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::control {

/// \brief A reply that lacks a field its view needs, or holds it with the wrong type; the message
/// names the field.
class ReplyError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief Azimuth bins a slice's sweep fills (docs/method.md: one per 15 deg).
inline constexpr int kBinsPerSlice = 24;

/// \brief One slice of a session: "name", "kind", "theta_i", "theta_v", "samples", "bins_filled",
/// and "samples_set_aside" / "samples_refused" / "damaged" / "refused" only when there are any.
struct SliceProgress {
  SliceId slice;
  std::size_t samples = 0;
  int binsFilled = 0;
  std::size_t samplesSetAside = 0;
  /// Of samplesSetAside, those refused sweep runs set aside (the rest: journal damage); kept after
  /// a redo, as samplesSetAside is. Nullopt from a daemon before it (refused then says why).
  std::optional<std::size_t> samplesRefused;
  bool damaged = false;
  /// Why a sweep of the slice was refused (its decoding shown broken; the samples it had then are
  /// set aside, kept in the session, used by no table), until the slice is redone.
  std::optional<std::string> refused;
};

/// \brief What replaying a session's journal could not tell for sure (the message names the
/// journal and line).
struct JournalDamageView {
  std::size_t line = 0;
  std::string message;
  std::vector<std::string> slicesSetAside;  ///< slice names
  std::size_t samplesSetAside = 0;
  std::size_t samplesLost = 0;
};

/// \brief A session as `session.new/show/resume` and the status give it. The status leaves out
/// "created", "directory" and the journal's recovery figures; `session.show` adds "current".
struct SessionView {
  std::string id;
  std::string material;
  std::optional<std::string> createdUtc;
  std::optional<std::string> directory;
  std::size_t samples = 0;
  std::vector<SliceProgress> slices;
  std::optional<std::size_t> tornTailBytesDropped;
  std::vector<std::size_t> corruptJournalLines;
  std::vector<JournalDamageView> journalDamage;
  std::optional<bool> current;
};

/// \brief The sweep of one slice, as `sweep.*` and the status give it. "view_elevation_error_deg"
/// is always there (null before a posed frame); "pause_reason" only while paused.
struct SweepView {
  SliceId slice;
  std::string state;  ///< "capturing", "paused", or (the reply to sweep.stop) "stopped"
  std::vector<bool> bins;
  int binsFilled = 0;
  /// Bins (indices of `bins`) of an HDR sweep whose value rests on a cell clipped at every
  /// exposure (AzimuthBins::clippedBins): a lower bound until a shorter exposure sees them.
  std::vector<int> clippedBins;
  std::size_t samples = 0;
  std::size_t acceptedThisRun = 0;
  std::map<std::string, std::size_t> rejected;  ///< frames by reject reason
  std::optional<double> viewElevationErrorDeg;
  std::optional<std::string> pauseReason;
};

/// \brief The isotropy test's answer in the status: either an error, or a verdict ("isotropic" is
/// null when the slices cannot tell).
struct IsotropyView {
  std::optional<std::string> error;
  std::optional<bool> isotropic;
  bool informative = true;
  bool axialSweepsNeeded = true;
  std::string reason;
};

/// \brief A sweep's raw-frame recording (record_frames), in the status and the stop's reply.
struct RecordingView {
  std::string directory;
  std::size_t framesWritten = 0;
  std::size_t framesQueued = 0;
  std::size_t framesDropped = 0;
  std::optional<std::string> error;
};

/// \brief A sweep's texture capture (texture_resolution), in the status and the stop's reply:
/// the slice's progress, and what the session's texture store holds (lib/btf's store fills all).
struct TextureProgressView {
  int resolution = 0;
  int binsFilled = 0;
  std::size_t framesStored = 0;
  std::string directory;
  std::optional<std::size_t> sessionFramesStored;  ///< every slice's frames in the store
  std::optional<double> storedMb;                  ///< the store's size on disk
  std::optional<std::size_t> damagedFramesRemoved;  ///< by the store's recovery when it opened
};

/// \brief A live camera's frames in the sweep run (or the last one), as the LED strobe counted
/// them: "camera_frames".
struct CameraFramesView {
  std::uint64_t delivered = 0;
  std::uint64_t dropped = 0;  ///< sequence gaps: frames the camera lost
  std::string ledPattern;     ///< the strobe's pattern, e.g. "on on off off"
  /// Frames with one LED state over their rows of interest, of those judged (0 before any).
  double ledCleanFraction = 0.0;
  std::string timing;  ///< how the frames' exposure times are known, in words
};

/// \brief How the sweep run's 8-bit frames become linear light (docs/linear-light.md):
/// "decoding" is "linear", "srgb", "measured-curve", ... or "measuring" while the bracket runs.
struct DecodingView {
  std::string decoding;
  std::string note;  ///< the fit's summary, or why this decoding
};

/// \brief The room light the sweep run's samples saw (each figure once it is known).
struct RoomLightView {
  std::optional<double> toLed;        ///< median room-to-LED ratio on the white references
  std::optional<double> change;       ///< median change between LED-off frames, relative
  std::optional<double> changeToLed;  ///< change x toLed: as a fraction of the LED's light
};

/// \brief Whether the sweep run's 8-bit frames decode the same way from frame to frame and stay
/// above black (daemon::DecodingWatch; docs/linear-light.md, "Checks on the decoding"): each
/// figure once known.
struct DecodingCheckView {
  /// Median of the black patch's reading against the white references (1: decoded right).
  std::optional<double> blackReading;
  /// Mean step of that reading from a sample to the next frame's, relative and signed, and that
  /// mean in its standard errors: a tone curve the camera stretches per frame from the frame
  /// before (adaptive contrast) steps it one way every LED block, noise either way.
  std::optional<double> blackReadingStep;
  std::optional<double> blackReadingStepSigmas;
  /// The window's channel with the most pixels at code 0 ("R", "G", "B") and its median fraction
  /// over the latest samples: nearly all where a colour matrix took the light below black.
  std::optional<std::string> windowAtBlackChannel;
  std::optional<double> windowAtBlack;
  /// The window's channel whose LED light (window less room light) sits lowest against its own
  /// spread ("R", "G", "B"), the fraction of the latest samples in which that light is at or
  /// below 0, the fraction exactly 0, its median in robust standard errors (negative: below 0)
  /// and, from 8 samples, the mean of those near the median in its standard errors. The LED
  /// only adds light: a median or mean far below 0, or light pinned at exactly 0, is a decoding
  /// that lost the channel. Whether that refuses the sweep is windowUnlitVerdict's.
  std::optional<std::string> windowUnlitChannel;
  std::optional<double> windowUnlit;
  std::optional<double> windowUnlitAtZero;
  std::optional<double> windowUnlitSigmas;
  std::optional<double> windowUnlitMeanSigmas;
  /// What the refusal rule makes of it: not judged (RAW, too few samples), kept, refused, or
  /// only warned of (refuse_broken_decoding = false).
  std::optional<std::string> windowUnlitVerdict;
  /// The window channel whose light over the white references' (the sample's value) steps most
  /// from a sample to the next frame's, in standard errors, that mean relative step and its
  /// standard errors: a tone curve stretched per frame from the frame before moves a dark
  /// channel against the whites one way every LED block; one curve leaves noise.
  std::optional<std::string> windowStepChannel;
  std::optional<double> windowStep;
  std::optional<double> windowStepSigmas;
};

/// \brief The Raspberry Pi tuning file slicecapd chose for its camera (docs/real-sensors.md, "The
/// processed path's tuning file"): "tuning_file".
struct TuningFileView {
  std::string setting;              ///< "auto", "off" or the configured path
  std::optional<std::string> file;  ///< the file the camera's IPA reads; none: its own
  std::string reason;               ///< why, in words
};

/// \brief A bin of a swept slice to pass over again, slowly (capture::binsToPassAgain): "slice"
/// (as a sweep's), "azimuth_deg" (the bin centre's slice parameter) and "reason".
struct PassAgainView {
  SliceId slice;
  double azimuthDeg = 0.0;
  std::string reason;  ///< "empty" or "peak_not_reached"
};

/// \brief The texture verdict of a finished sweep's window cells (capture::cellTextureOf;
/// docs/method.md §9.4): how the export's cell slices and the bins to pass again read them.
/// "cell_texture" in the status: "slice" (as a sweep's), "action", "spread_percent", "reason".
struct CellTextureView {
  SliceId slice;
  std::string action;  ///< "as read", "albedo-normalised" or "window centres"
  /// How far the cells' albedo factors differ between positions beyond the scatter of frames
  /// (capture::CellTexture::spreadPercent), about in percent; none: too few frames with
  /// every cell clear of the noise to measure it.
  std::optional<double> spreadPercent;
  std::string reason;  ///< why that action, with the figures the rule compared
};

/// \brief What `status` answers. The session manager fills session, sweep, next, isotropy,
/// pass_again, cell_texture and error; the daemon's sweep devices fill the rest. statusFields() says what each key means.
struct StatusView {
  std::optional<SessionView> session;
  std::optional<SweepView> sweep;
  std::string next;
  std::optional<IsotropyView> isotropy;
  std::vector<PassAgainView> passAgain;  ///< the session's slices, sweep order, ascending bins
  /// The session's finished sweeps with window cells, sweep order (the running one is left out).
  std::vector<CellTextureView> cellTextures;
  std::optional<std::string> error;
  std::optional<RecordingView> recording;
  std::optional<TextureProgressView> texture;
  std::optional<std::string> exposure;
  std::optional<std::string> hdr;
  std::optional<CameraFramesView> cameraFrames;
  std::optional<DecodingView> decoding;
  std::optional<RoomLightView> roomLight;
  std::optional<DecodingCheckView> decodingCheck;
  std::optional<TuningFileView> tuningFile;
  std::vector<std::string> warnings;
};

/// \brief One key of the status reply ("camera_frames.dropped" for a key inside an object) and
/// what it holds, for `slicecap status --help` and docs/reference/protocol.md.
struct ReplyField {
  std::string key;
  std::string meaning;
};
/// \brief Every key toJson(StatusView) can write, with the device objects' keys inside them, in
/// the reply's order of reading (a test holds it equal to what toJson writes).
const std::vector<ReplyField>& statusFields();

/// \brief The reply to `sweep.stop`: the stopped sweep with what it kept besides its samples.
struct SweepStopView {
  SweepView sweep;
  std::optional<RecordingView> recording;
  std::optional<TextureProgressView> texture;
};

/// \brief One session of `session.list`: "damaged" replaces created/material's meaning when the
/// session cannot be read.
struct SessionListEntry {
  std::string id;
  std::string material;
  std::string createdUtc;
  bool current = false;
  std::optional<std::string> damaged;
};

/// \brief What `export` answers: the files written (absolute paths on the box), the method of the
/// first table, and the session's texture folder when it is to be copied too.
struct ExportView {
  std::string session;
  std::string directory;
  std::vector<std::string> files;
  std::string method;
  std::optional<std::string> material;  ///< the fitted material's one-line summary
  std::vector<std::string> warnings;
  std::optional<std::string> texture;         ///< the texture folder to copy
  std::vector<std::string> textureFiles;      ///< its files, relative to it, to copy
  std::optional<std::string> textureSkipped;  ///< why the texture is not exported this time
};

// To JSON: what the daemon sends. From JSON: what the client reads; a reply without a field
// these need throws ReplyError naming the field.
nlohmann::json toJson(const SliceProgress& slice);
nlohmann::json toJson(const JournalDamageView& damage);
nlohmann::json toJson(const SessionView& session);
nlohmann::json toJson(const SweepView& sweep);
nlohmann::json toJson(const IsotropyView& isotropy);
nlohmann::json toJson(const RecordingView& recording);
nlohmann::json toJson(const TextureProgressView& texture);
nlohmann::json toJson(const StatusView& status);
nlohmann::json toJson(const SweepStopView& stop);
nlohmann::json toJson(const SessionListEntry& entry);
nlohmann::json toJson(const ExportView& reply);

/// \brief The slice's own fields ("name", "kind", "theta_i", "theta_v").
nlohmann::json sliceJson(const SliceId& slice);

SessionView sessionFromJson(const nlohmann::json& json);
SweepView sweepFromJson(const nlohmann::json& json);
IsotropyView isotropyFromJson(const nlohmann::json& json);
RecordingView recordingFromJson(const nlohmann::json& json);
TextureProgressView textureProgressFromJson(const nlohmann::json& json);
StatusView statusFromJson(const nlohmann::json& json);
std::vector<SessionListEntry> sessionListFromJson(const nlohmann::json& json);
ExportView exportFromJson(const nlohmann::json& json);

}  // namespace slicecap::control
