// The daemon's CaptureRig from slicecapd.conf: the configured cameras, and the capture pipeline
// over each slice's target and camera model.
#pragma once

#include "slicecap/capture/frame_pipeline.hpp"
#include "slicecap/daemon/capture_rig.hpp"
#include "slicecap/rig/configured_devices.hpp"

namespace slicecap::rig {

/// \brief Each slice's camera from `sources`; its pipeline and response bracket over the slice's
/// target and camera model (sources.rigFor, which follows the size the camera delivers).
class ConfiguredCaptureRig final : public daemon::CaptureRig {
 public:
  ConfiguredCaptureRig(CameraSources sources, capture::PipelineSettings settings)
      : sources_(std::move(sources)), settings_(std::move(settings)) {}

  std::shared_ptr<hal::Camera> camera(const SliceId& slice) override;
  capture::LiveFrameProcessor pipeline(const SliceId& slice, capture::FrameObserver observer,
                                       const std::optional<ToneCurve>& toneCurve) override;
  std::optional<daemon::BracketSubject> bracketSubject(const SliceId& slice) override;

 private:
  CameraSources sources_;
  capture::PipelineSettings settings_;
};

/// \brief The pipeline settings slicecapd.conf gives every sweep (the tone curve comes per run).
capture::PipelineSettings pipelineSettingsFrom(const daemon::DaemonConfig& config);

}  // namespace slicecap::rig
