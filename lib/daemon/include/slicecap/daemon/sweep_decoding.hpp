// How a live sweep's frames become linear light (issue 27 item 2): a processed camera's response
// measured from a bracket at sweep start, a linear stream taken as it is, or the sRGB curve as a
// stated fallback; and the bracket itself as a sequence of steps the daemon carries out.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/capture/response_curve.hpp"
#include "slicecap/control/reply_views.hpp"
#include "slicecap/hal/camera.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/io/recording.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::daemon {

/// \brief <session>/decoding/<slice>.json: each sweep run's decoding (toJson below).
inline constexpr const char* kDecodingFolder = "decoding";
/// \brief <session>/brackets/<slice>/run-N: the bracket frames, a recording (record_frames).
inline constexpr const char* kBracketFolder = "brackets";

/// \brief slicecapd.conf `decoding`: auto measures the response of an 8-bit camera at each sweep
/// start (a linear stream needs none) and falls back to sRGB, with a warning, when the bracket
/// cannot be fitted; measured-curve is auto that also warns when a camera is linear (nothing to
/// measure); srgb never brackets (a camera known to encode sRGB, or to save the second it takes).
enum class DecodingMode { Auto, MeasuredCurve, Srgb };

/// \brief "auto", "measured-curve", "srgb".
std::string toString(DecodingMode mode);
/// \brief The mode a configuration value names. Throws ConfigError naming the value.
DecodingMode decodingModeFromString(const std::string& value);

/// \brief What the bracket is fitted against: the target in view and the camera's model.
struct BracketSubject {
  vision::TargetGeometry target;
  vision::CameraModel camera;
};

/// \brief The decoding a sweep run uses, and why.
struct SweepDecoding {
  io::RecordedDecoding decoding;  ///< what the sweep's frames are read through
  /// One line: the fit's summary, or why this decoding (for the status and the session).
  std::string note;
  /// A weaker mode than asked for (sRGB for an 8-bit camera whose bracket failed), naming the
  /// camera and what to configure; empty otherwise.
  std::string warning;
  /// The bracket frames (LED on, one per exposure), kept so the fit can be redone on a desktop.
  std::vector<hal::Frame> bracketFrames;
};

/// \brief The session's record of a sweep run's decoding: kind, note, warning, curve points.
nlohmann::json toJson(const SweepDecoding& decoding, const std::string& cameraId);

/// \brief Adds a sweep run's decoding check (DecodingWatch: its figures and warnings) to that
/// run's record `file` (<session>/decoding/<slice>.json) as "check", so the session keeps what the
/// status said. Throws io::IoError naming the file when it cannot be read or written.
void recordDecodingCheck(const std::filesystem::path& file, const control::DecodingCheckView& figures,
                         const std::vector<std::string>& warnings);

/// \brief Every warning of a "check" in <session>/decoding/*.json, each led by its slice's
/// folder name (for the session's export); a record that cannot be read is said as such.
std::vector<std::string> recordedDecodingWarnings(const std::filesystem::path& session);

/// \brief The bracket at sweep start: locks each setting of a BracketPlan in turn, keeps the first
/// frame taken under each lock, then locks the metered setting again and skips frames until it
/// is in effect (the sweep's frames must all have the metered exposure).
class ResponseBracket {
 public:
  /// \brief `metered`: the sweep's setting (what the metering locked, or exposure_us); `locks`:
  /// the camera's locks accepted since it started (FrameMetadata::exposureLocks counts them).
  ResponseBracket(const hal::ExposureSetting& metered, std::uint32_t locks,
                  capture::BracketPlan plan = {}, double maxExposureUs = 33'333.0,
                  double maxGain = 16.0);

  /// \brief The first setting to lock.
  const hal::ExposureSetting& firstSetting() const { return settings_.front(); }
  /// \brief The camera accepted the last lock (call for every lock the camera made).
  void accepted();
  /// \brief The camera refused the last lock: the bracket ends unfitted, saying why.
  void refused(const std::string& reason);

  struct Step {
    enum class Kind { Wait, Lock, Done };
    Kind kind = Kind::Wait;
    hal::ExposureSetting setting;  ///< Lock: the next setting
  };
  /// \brief One frame from the camera while the bracket runs.
  Step onFrame(const hal::Frame& frame);

  /// \brief The bracket frames kept so far (complete once Done, unless failure() says otherwise).
  std::vector<hal::Frame>& frames() { return frames_; }
  /// \brief Why the bracket ended early (a refused lock, a camera that never applied one); empty
  /// when every setting got its frame.
  const std::string& failure() const { return failure_; }

 private:
  std::vector<hal::ExposureSetting> settings_;  // the plan's, then the metered one again
  std::size_t current_ = 0;                     // index of the setting last locked
  std::uint32_t locks_ = 0;
  int framesSinceLock_ = 0;
  bool done_ = false;
  std::vector<hal::Frame> frames_;
  std::string failure_;
};

/// \brief The decoding of a sweep on a camera whose frames have `encoding`, when no bracket is
/// taken: Linear16 is linear; 8-bit is sRGB (noted, with `why` as the warning when not empty).
SweepDecoding decodingWithoutBracket(PixelEncoding encoding, DecodingMode mode,
                                     const std::string& cameraId, const std::string& why);

/// \brief Fits the bracket (capture::fitResponse) and says the sweep's decoding: measured-curve
/// with the fit's summary, or sRGB with a warning that names the camera, says why (the fit's
/// ResponseFitError, or `bracketFailure`) and what to configure. Never throws for a bad bracket.
SweepDecoding decodingFromBracket(std::vector<hal::Frame> bracket, const std::string& bracketFailure,
                                  const BracketSubject& subject, const std::string& cameraId);

}  // namespace slicecap::daemon
