// The session's texture: the pipeline's accepted frames rectified, binned and combined per sweep.
#include "slicecap/btf/texture_capture.hpp"

#include <algorithm>
#include <stdexcept>

#include "slicecap/btf/btf_error.hpp"
#include "slicecap/capture/recording_processor.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/core/core_error.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::btf {

std::optional<double> textureSliceParameterDeg(const capture::FrameOutcome& outcome,
                                               SliceKind kind) {
  const auto& m = outcome.measurement;
  if (outcome.kind != capture::FrameOutcome::Kind::Sample || !outcome.sample || !m.pose ||
      !m.fittedLight)
    return std::nullopt;
  return sliceParameterDeg(kind,
                           {outcome.sample->light, outcome.sample->view, outcome.sample->value});
}

TextureFrame textureFrameOf(const TextureGrid& grid, const vision::CameraModel& camera,
                            const hal::Frame& frame, const capture::FrameOutcome& outcome,
                            std::span<const capture::AmbientTerm> ambient, SliceKind kind,
                            const RectifyParams& params) {
  const std::optional<double> parameterDeg = textureSliceParameterDeg(outcome, kind);
  if (!parameterDeg)
    throw BtfError("texture: only an accepted sample with its pose and light fit");
  const auto& m = outcome.measurement;
  const UnitVector toLight = toUnitVector(outcome.sample->light);
  const auto& p = m.fittedLight->positionMm;
  const double distanceMm = Eigen::Vector3d(p.x, p.y, p.z).norm();
  TextureFrame texture;
  texture.sliceParameterDeg = *parameterDeg;
  texture.cameraMm = m.pose->cameraCentreMm();
  texture.lightMm = Eigen::Vector3d(toLight.x, toLight.y, toLight.z) * distanceMm;
  texture.texels = rectifyFrame(grid, camera, frame, ambient, {*m.pose, *m.fittedLight}, params);
  return texture;
}

TextureCapture::TextureCapture(const vision::CameraModel& camera, const vision::RectMm& window,
                               const TextureCaptureParams& params)
    : grid_(params.resolution, window), camera_(camera), params_(params) {
  std::string error;
  if (!camera_.isValid(&error)) throw BtfError("texture capture: camera: " + error);
  if (params.framesPerBin < 1)
    throw BtfError("texture capture: frames per bin must be at least 1");
}

void TextureCapture::startSlice(const SliceId& slice, std::optional<ToneCurve> toneCurve) {
  finishSlice();
  for (const SliceTexture& done : slices_)
    if (done.slice == slice)
      throw BtfError("texture capture: slice " + toString(slice) +
                     " was already captured");
  active_.emplace(slice, grid_.texelCount(), params_.framesPerBin);
  activeRectify_ = params_.rectify;
  if (toneCurve) activeRectify_.toneCurve = std::move(toneCurve);
}

void TextureCapture::add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
                         std::span<const capture::AmbientTerm> ambient) {
  if (!active_) throw std::logic_error("texture capture: a frame outside a sweep");
  if (!textureSliceParameterDeg(outcome, active_->slice().kind)) return;
  active_->add(
      textureFrameOf(grid_, camera_, frame, outcome, ambient, active_->slice().kind, activeRectify_));
  peakBytes_ = std::max(peakBytes_, memoryBytes());
}

void TextureCapture::finishSlice() {
  if (!active_) return;
  slices_.push_back(active_->combine());
  active_.reset();
  peakBytes_ = std::max(peakBytes_, memoryBytes());
}

std::size_t TextureCapture::memoryBytes() const {
  std::size_t bytes = active_ ? active_->memoryBytes() : 0;
  for (const SliceTexture& s : slices_)
    bytes += s.memoryBytes();
  return bytes;
}

TextureSweep::TextureSweep(const std::filesystem::path& directory, const SliceId& slice,
                           const vision::CameraModel& camera, const TextureStoreLayout& layout,
                           const RectifyParams& rectify, const std::vector<TextureRun>& refused)
    : store_(TextureStore::openOrCreate(directory, layout, refused)),
      runStart_(store_.beginRun(slice)),
      slice_(slice),
      camera_(camera),
      grid_(store_.grid()),
      rectify_(rectify) {
  std::string error;
  if (!camera_.isValid(&error)) throw BtfError("texture capture: camera: " + error);
}

bool TextureSweep::add(const hal::Frame& frame, const capture::FrameOutcome& outcome,
                       std::span<const capture::AmbientTerm> ambient) {
  const std::optional<double> parameterDeg = textureSliceParameterDeg(outcome, slice_.kind);
  if (!parameterDeg || !store_.wouldKeep(slice_, *parameterDeg)) return false;
  return store_.add(slice_,
                    textureFrameOf(grid_, camera_, frame, outcome, ambient, slice_.kind, rectify_));
}

SessionTexture captureRecordings(const std::vector<std::filesystem::path>& recordings,
                                 const capture::PipelineSettings& settings,
                                 const TextureCaptureParams& params,
                                 const std::function<void(const std::string&)>& log) {
  if (recordings.empty()) throw BtfError("texture capture: no recordings");
  const io::Recording first = io::readRecording(recordings.front());
  SessionTexture session{TextureCapture(first.camera, first.target.window, params), {}};
  for (const std::filesystem::path& directory : recordings) {
    const io::Recording header = io::readRecording(directory);
    if (header.camera.intrinsics.widthPx != first.camera.intrinsics.widthPx ||
        header.camera.intrinsics.heightPx != first.camera.intrinsics.heightPx ||
        !(header.target.window == first.target.window))
      throw BtfError(directory.string() + ": another camera size or window than " +
                     recordings.front().string() +
                     " (one texture needs one target and camera)");
    if (!header.slice)
      throw BtfError(directory.string() +
                     ": recording.json has no slice (a calibration recording?)");
    try {
      // Rectified through the same decoding as processRecording reads the sweep with.
      session.texture.startSlice(
          header.slice->id,
          settings.toneCurve
              ? settings.toneCurve
              : header.decoding.value_or(io::RecordedDecoding::defaultFor(header.encoding))
                    .toneCurve());
    } catch (const BtfError& error) {
      throw BtfError(directory.string() + ": " + error.what());
    } catch (const CoreError& error) {  // the recording's tone curve
      throw BtfError(directory.string() + ": " + error.what());
    }
    const capture::RecordingResult result =
        capture::processRecording(directory, settings,
                                  [&](const hal::Frame& frame, const capture::FrameOutcome& outcome,
                                      const std::vector<capture::AmbientTerm>& ambient) {
                                    session.texture.add(frame, outcome, ambient);
                                  });
    session.texture.finishSlice();
    for (const SliceSample& sample : result.bins.combine())
      session.averageSlices.add(result.slice, sample);
    if (log)
      log(toString(result.slice) + " (" + directory.string() +
          "): " + std::to_string(result.bins.filledCount()) + " of " +
          std::to_string(result.bins.binCount()) + " bins");
  }
  return session;
}

}  // namespace slicecap::btf
