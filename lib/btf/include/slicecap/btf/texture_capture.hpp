// Texture capture of a whole session: every accepted frame rectified and binned per slice, the
// finished sweeps combined, beside the window-average slices of today's pipeline.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "slicecap/btf/rectifier.hpp"
#include "slicecap/btf/slice_texture.hpp"
#include "slicecap/btf/texture_grid.hpp"
#include "slicecap/btf/texture_store.hpp"
#include "slicecap/capture/frame_outcome.hpp"
#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::btf {

/// \brief Options of a texture capture.
struct TextureCaptureParams {
  int resolution = 128;  ///< texels across the window
  int framesPerBin = 5;  ///< frames a bin keeps (median); bounds the active sweep's memory
  RectifyParams rectify;
};

/// \brief The slice parameter a frame's texture would be binned at: that of its window-centre
/// sample, for an accepted sample whose pose and light fit are known; nothing otherwise (no
/// texture). Decides, before the costly rectification, whether a bin would keep the frame.
std::optional<double> textureSliceParameterDeg(const capture::FrameOutcome& outcome,
                                               SliceKind kind);

/// \brief An accepted frame's texture (textureSliceParameterDeg must have given a parameter;
/// BtfError otherwise): its window rectified on `grid` with the room-light term
/// `ambient`, and the camera and LED positions that give every texel its own directions (the LED
/// where the sample's light direction points, at the light fit's distance).
TextureFrame textureFrameOf(const TextureGrid& grid, const vision::CameraModel& camera,
                            const hal::Frame& frame, const capture::FrameOutcome& outcome,
                            std::span<const capture::AmbientTerm> ambient, SliceKind kind,
                            const RectifyParams& params = {});

/// \brief Collects a session's texture sweep by sweep. Memory: the active sweep's bins (24 x
/// framesPerBin x N^2 x 12 bytes at most) plus every finished sweep's combined bins (24 x N^2 x 12
/// bytes each; 8 sweeps at N = 128: 9.4 million floats, 37.7 MB).
class TextureCapture {
 public:
  /// \brief Throws BtfError for a bad resolution or camera.
  TextureCapture(const vision::CameraModel& camera, const vision::RectMm& window,
                 const TextureCaptureParams& params = {});

  /// \brief Starts a sweep (finishing the previous one); its 8-bit frames are decoded through
  /// `toneCurve` when given (the sweep's measured response, as its pipeline reads them), else as
  /// params.rectify says. Throws BtfError when the slice was already captured.
  void startSlice(const SliceId& slice, std::optional<ToneCurve> toneCurve = std::nullopt);
  /// \brief One frame of the active sweep: an accepted sample (with its pose and light fit) is
  /// rectified and binned; anything else is ignored. `ambient` is the room-light term the
  /// pipeline corrected it with (FramePipeline::ambientTermsFor; empty: none). Throws
  /// std::logic_error outside a sweep.
  void add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
           std::span<const capture::AmbientTerm> ambient);
  /// \brief Combines the active sweep's bins into its SliceTexture (nothing if none is active).
  void finishSlice();

  const TextureGrid& grid() const { return grid_; }
  const vision::CameraModel& camera() const { return camera_; }
  /// \brief The finished sweeps, in the order they were captured.
  const std::vector<SliceTexture>& slices() const { return slices_; }
  /// \brief Texel bytes held now, and the most held at any time.
  std::size_t memoryBytes() const;
  std::size_t peakMemoryBytes() const { return peakBytes_; }

 private:
  TextureGrid grid_;
  vision::CameraModel camera_;
  TextureCaptureParams params_;
  RectifyParams activeRectify_;  // the active sweep's: params_.rectify with its decoding
  std::optional<SliceTextureBins> active_;
  std::vector<SliceTexture> slices_;
  std::size_t peakBytes_ = 0;
};

/// \brief One slice's sweep into a TextureStore, as the daemon captures it: a frame the store
/// would keep is rectified and stored at once (durable); the others are not even rectified, so a
/// long sweep costs neither memory nor time once its bins hold frames near their centres.
class TextureSweep {
 public:
  /// \brief Opens (or creates) the store in `directory`; throws as TextureStore::openOrCreate, and
  /// BtfError for a bad camera. `refused`: the journal's refused runs (TextureStore::open).
  TextureSweep(const std::filesystem::path& directory, const SliceId& slice,
               const vision::CameraModel& camera, const TextureStoreLayout& layout,
               const RectifyParams& rectify = {}, const std::vector<TextureRun>& refused = {});

  /// \brief One frame with its outcome and room-light term; returns whether it was stored.
  /// Throws io::IoError when it cannot be written.
  bool add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
           std::span<const capture::AmbientTerm> ambient);
  const TextureStore& store() const { return store_; }
  const SliceId& slice() const { return slice_; }
  /// \brief A sweep run begins (the sweep opened, or continued after a pause): the frames stored
  /// from now on are the run's (TextureStore::beginRun).
  void beginRun() { runStart_ = store_.beginRun(slice_); }
  /// \brief The run was kept: the earlier frames it replaced are deleted (TextureStore::keepRun).
  void keepRun() { store_.keepRun(slice_); }
  /// \brief The run was refused: its frames set aside and the earlier frames they replaced put
  /// back (TextureStore::setAside); how many were set aside.
  std::size_t setAsideRun() { return store_.setAside(slice_, runStart_, store_.nextSequence()); }
  /// \brief The run's frames so far: numbered from its first to the store's next, excluded.
  TextureRun run() const { return {slice_, runStart_, store_.nextSequence()}; }

 private:
  TextureStore store_;
  std::uint64_t runStart_ = 0;
  SliceId slice_;
  vision::CameraModel camera_;
  TextureGrid grid_;
  RectifyParams rectify_;
};

/// \brief What `captureRecordings` produced: the texture and the window-average slices (the
/// average ABRDF's input, exactly what `slicecap process` gives).
struct SessionTexture {
  TextureCapture texture;
  SliceSet averageSlices;
};

/// \brief Runs every recording (one slice each) through the capture pipeline and the texture
/// capture. The camera and window come from the first recording; a recording with another
/// camera size or window, or a slice given twice, throws BtfError naming it. I/O
/// errors throw io::IoError naming the file. `log` (if set) gets one line per recording.
SessionTexture captureRecordings(const std::vector<std::filesystem::path>& recordings,
                                 const capture::PipelineSettings& settings,
                                 const TextureCaptureParams& params,
                                 const std::function<void(const std::string&)>& log = {});

}  // namespace slicecap::btf
