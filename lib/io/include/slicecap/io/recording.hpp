// A recording: a directory with recording.json (camera, encoding, slice, target, frames) and PNG
// frames; what a camera session and the virtual rig both write (docs/recording-format.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "slicecap/core/image.hpp"
#include "slicecap/core/pixel_encoding.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/core/tone_curve.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::io {

/// \brief The newest version this build reads. 2 added `decoding` (a version 1 reader would
/// decode a measured-curve recording as sRGB without a word); 3 added `decoding_black16` (a
/// version 2 reader would read a RAW sweep's frames, stored above a black of 4096, 1/16 of full
/// scale too bright). A manifest is written at the least version its fields need.
inline constexpr int kRecordingFormatVersion = 3;
/// \brief The manifest's file name inside a recording directory.
inline constexpr const char* kRecordingManifest = "recording.json";
/// \brief An HDR sweep alternates at most this many exposure levels (frames[].exposure_level).
inline constexpr int kMaxExposureLevels = 3;

/// \brief One frame's entry: its PNG (relative to the recording directory) and what the camera and
/// the LED were doing.
/// \brief What the LED did while a live frame's rows were exposed (hal::LedExposure, on the
/// recording's time line): enough to judge the frame again on a desktop, for any rows.
struct RecordedLedExposure {
  std::int64_t row0StartUs = 0;  ///< start of row 0's exposure
  double lineTimeUs = 0.0;       ///< row-to-row start delay (0: global shutter)
  double exposureUs = 0.0;       ///< how long each row was exposed
  double guardUs = 0.0;          ///< a switch's uncertainty either side
  bool onAtStart = false;        ///< the LED's state at row 0's start
  std::vector<std::pair<std::int64_t, bool>> changes;  ///< (time, on) after row0StartUs
  friend bool operator==(const RecordedLedExposure&, const RecordedLedExposure&) = default;
};

struct RecordedFrame {
  std::string file;
  std::int64_t timestampUs = 0;  ///< capture time, microseconds, strictly increasing
  bool ledOn = true;
  double exposureUs = 0.0;  ///< exposure time, microseconds (> 0)
  double gain = 1.0;        ///< total (analogue x digital) gain, >= 1 on a real sensor, > 0 here
  /// A live frame's LED exposure (slicecapd's record_frames): the LED switched while some rows
  /// were exposed; `ledOn` is then only the majority. Absent in simulated recordings.
  std::optional<RecordedLedExposure> ledExposure{};
  /// An HDR sweep's exposure level (0 = the longest, 1, 2 = shorter; docs/recording-format.md):
  /// the sweep alternates LED pairs over the levels, and each LED-off frame is the room light of
  /// the LED-on frames of its own level. Absent: one exposure (what every older recording means).
  std::optional<int> exposureLevel{};
  friend bool operator==(const RecordedFrame&, const RecordedFrame&) = default;
};

/// \brief The slice a recording was taken for: kind, nominal elevations, the axial offset.
struct RecordedSlice {
  SliceId id;
  double alphaDeg = kAxialOffsetDeg;
  friend bool operator==(const RecordedSlice&, const RecordedSlice&) = default;
};

/// \brief How the frames' samples become linear light (docs/linear-light.md).
struct RecordedDecoding {
  enum class Kind {
    Srgb,           ///< 8-bit through the sRGB curve (what version 1 recordings of srgb8 mean)
    MeasuredCurve,  ///< 8-bit through `curve`, the camera's response measured at sweep start
    Linear,         ///< proportional to the sensor's signal (linear16; or 8-bit linear)
  };
  Kind kind = Kind::Srgb;
  std::optional<ToneCurve> curve{};  ///< set exactly when kind is MeasuredCurve
  /// Linear only: the sample value of no light (hal::Frame::black16; a RAW sweep's frames keep
  /// their read noise above hal::kDecodedBlack16). 0: black is 0.
  std::uint16_t black16 = 0;

  /// \brief What a recording without `decoding` means: sRGB for srgb8, linear for linear16.
  static RecordedDecoding defaultFor(PixelEncoding encoding);
  /// \brief The curve 8-bit frames are read through: `curve`, ToneCurve::linear(), or nullopt for
  /// sRGB (the pipeline's default).
  std::optional<ToneCurve> toneCurve() const;
  friend bool operator==(const RecordedDecoding& a, const RecordedDecoding& b);
};

/// \brief "srgb", "measured-curve" or "linear".
std::string toString(RecordedDecoding::Kind kind);

/// \brief Everything recording.json holds.
struct Recording {
  /// As read; a new recording's is 2, raised on writing to what its fields need (3 with a
  /// decoding's black16).
  int formatVersion = 2;
  std::string createdBy;  ///< e.g. "slicecap simulate 0.1.0"
  vision::CameraModel camera;
  /// When set, recording.json refers to this calibration file (e.g. from `slicecap calibrate`;
  /// relative to the directory, "../camera.json" for one shared by a session, or absolute)
  /// instead of embedding the camera; `camera` then holds what the file says.
  std::optional<std::string> calibrationFile;
  PixelEncoding encoding = PixelEncoding::Srgb8;
  /// nullopt: RecordedDecoding::defaultFor(encoding) (what recordings before version 2 mean).
  std::optional<RecordedDecoding> decoding{};
  std::optional<RecordedSlice> slice;  ///< absent for e.g. a calibration recording
  /// The capture's room_light_unseen gate when it was on (slicecapd.conf room_light_unseen_mm >
  /// 0): offline processing applies it unless told otherwise, so it reproduces the session.
  std::optional<double> roomLightUnseenMm;
  vision::TargetGeometry target;
  std::vector<RecordedFrame> frames;
  friend bool operator==(const Recording&, const Recording&) = default;
};

/// \brief Reads and validates `directory`/recording.json (or the file itself when given): every
/// field's type and range, the camera, the target, each frame's file (relative, inside the
/// directory, present), timestamps strictly increasing. Throws IoError "FILE: FIELD: problem",
/// e.g. "rec/recording.json: frames[3].exposure_us: expected a positive number, got -5".
Recording readRecording(const std::filesystem::path& directory);

/// \brief Writes `directory`/recording.json atomically (temporary file, fsync, rename). With a
/// calibrationFile the camera is not embedded. Throws IoError naming the path.
void writeRecordingManifest(const std::filesystem::path& directory, const Recording& recording);

/// \brief The directory's absolute path of a frame's file.
std::filesystem::path framePath(const std::filesystem::path& directory, const RecordedFrame& frame);

/// \brief Writes a recording frame by frame: each append writes the PNG, then rewrites the
/// manifest atomically, so a crash loses at most the frame being written.
class RecordingWriter {
 public:
  /// \brief Creates `directory` (it must not hold a recording.json yet) and writes the manifest of
  /// `header` (its frames must be empty). Throws IoError naming the directory.
  RecordingWriter(std::filesystem::path directory, Recording header);

  /// \brief Continues the recording in `directory` (e.g. after the writer's process was killed):
  /// readRecording validates it; a frame written after the manifest's last one is overwritten by
  /// the next append. Throws IoError naming the field, as readRecording.
  static RecordingWriter resume(const std::filesystem::path& directory);

  /// \brief Appends a frame: `image` must match the camera's size, have 1 or 3 channels and the
  /// encoding's bit depth; `frame.file` is set to frame-NNNNN.png. Throws IoError naming the file,
  /// or IoError for an image of the wrong shape or a timestamp that does not
  /// increase.
  const RecordedFrame& append(const Image& image, RecordedFrame frame);

  const Recording& recording() const { return recording_; }
  const std::filesystem::path& directory() const { return directory_; }

 private:
  RecordingWriter() = default;
  std::filesystem::path directory_;
  Recording recording_;
};

}  // namespace slicecap::io
