// The daemon's collaborators as the tests that need only a camera and a pipeline give them: a
// CaptureRig over one camera factory and one pipeline (no response bracket), and tables that
// reconstruct an empty table (no export is asked for).
#pragma once

#include <functional>
#include <memory>
#include <utility>

#include "slicecap/daemon/capture_rig.hpp"
#include "slicecap/daemon/session_tables.hpp"

namespace slicecap::test {

class OneCameraRig : public daemon::CaptureRig {
 public:
  OneCameraRig(std::function<std::shared_ptr<hal::Camera>()> camera,
               std::function<capture::LiveFrameProcessor(capture::FrameObserver)> pipeline)
      : camera_(std::move(camera)), pipeline_(std::move(pipeline)) {}
  std::shared_ptr<hal::Camera> camera(const SliceId&) override { return camera_(); }
  capture::LiveFrameProcessor pipeline(const SliceId&, capture::FrameObserver observer,
                                       const std::optional<ToneCurve>&) override {
    return pipeline_(std::move(observer));
  }
  std::optional<daemon::BracketSubject> bracketSubject(const SliceId&) override {
    return std::nullopt;
  }

 private:
  std::function<std::shared_ptr<hal::Camera>()> camera_;
  std::function<capture::LiveFrameProcessor(capture::FrameObserver)> pipeline_;
};

class EmptyTables : public daemon::SessionTables {
 public:
  Abrdf reconstruct(const SliceSet&, const std::string&) override { return Abrdf(); }
};

}  // namespace slicecap::test
