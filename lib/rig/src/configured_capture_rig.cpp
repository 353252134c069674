// Each slice's camera and pipeline, as slicecapd.conf configures them.
#include "configured_capture_rig.hpp"

namespace slicecap::rig {

std::shared_ptr<hal::Camera> ConfiguredCaptureRig::camera(const SliceId& slice) {
  return sources_.cameraFor(slice);
}

capture::LiveFrameProcessor ConfiguredCaptureRig::pipeline(const SliceId& slice,
                                                           capture::FrameObserver observer,
                                                           const std::optional<ToneCurve>& toneCurve) {
  const Rig rig = sources_.rigFor(slice);
  capture::PipelineSettings settings = settings_;
  // decoding (issue 27): until a bracket's curve is measured (and without one) frames are read
  // as sRGB.
  settings.toneCurve = toneCurve;
  return capture::makeLiveFramePipeline(rig.target, rig.camera, settings, std::move(observer));
}

// A live camera's bracket is fitted against the slice's target and camera model.
std::optional<daemon::BracketSubject> ConfiguredCaptureRig::bracketSubject(const SliceId& slice) {
  const Rig rig = sources_.rigFor(slice);
  return daemon::BracketSubject{rig.target, rig.camera};
}

capture::PipelineSettings pipelineSettingsFrom(const daemon::DaemonConfig& config) {
  capture::PipelineSettings settings;
  // Without alternation there is no LED-off frame to measure the room light with.
  settings.requireAmbient = config.ledAlternate;
  settings.noise = {config.sensorReadNoise, config.sensorFullWellElectrons};
  // The offline default's room-light term (processRecording): each LED-on frame waits for the
  // LED-off frame after it (capture::makeLiveFramePipeline) and takes the room light from both
  // sides, each LED-off frame read at its own pose, so a session's recordings processed by
  // `slicecap capture-offline` give the live samples. One side alone is biased along a sweep
  // (a specular material's reflection of the room changes) and by a flicker the frame duration
  // does not hide.
  settings.poseAmbientFrames = config.ledAlternate;
  settings.maxRoomLightDistanceMm = config.roomLightUnseenMm;
  return settings;
}

}  // namespace slicecap::rig
