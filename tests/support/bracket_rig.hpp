// A still model camera (hal::ModelCamera: the IMX708's tone curve, colour gains, noise) over the
// virtual rig's target with the LED on: brackets for the response fit, and the scene's truth.
#pragma once

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <vector>

#include "slicecap/capture/response_curve.hpp"
#include "slicecap/hal/clock.hpp"
#include "slicecap/hal/led_timeline.hpp"
#include "slicecap/hal/model_camera.hpp"
#include "slicecap/sim/renderer.hpp"

namespace slicecap::test {

/// \brief The rig held still: one camera pose and one light position, rendered once.
class StillScene final : public hal::SceneSource {
 public:
  StillScene(std::shared_ptr<const sim::FrameRenderer> renderer, const vision::Pose& pose,
             const Eigen::Vector3d& lightMm)
      : light_(std::make_shared<hal::SceneLight>()) {
    sim::FrameScene scene{{pose}, lightMm, true, 1e6, 1.0, std::nullopt, 0};
    const std::vector<float> lit = renderer->renderLinear(scene);  // per second, unit gain
    scene.ledOn = false;
    light_->widthPx = renderer->camera().intrinsics.widthPx;
    light_->heightPx = renderer->camera().intrinsics.heightPx;
    light_->ambientRate = renderer->renderLinear(scene);
    light_->ledRate.resize(lit.size());
    for (std::size_t i = 0; i < lit.size(); ++i)
      light_->ledRate[i] = std::max(0.0f, lit[i] - light_->ambientRate[i]);
  }
  std::string id() const override { return "still rig"; }
  std::shared_ptr<const hal::SceneLight> lightAt(std::int64_t) override { return light_; }
  const hal::SceneLight& light() const { return *light_; }

 private:
  std::shared_ptr<hal::SceneLight> light_;
};

/// \brief The camera 300 mm from the window at 30 deg elevation, the LED 300 mm away at 30 deg
/// on the other side (the default target, the default simulated camera).
inline vision::Pose stillPose() {
  const double t = 30.0 * M_PI / 180.0;
  return vision::lookAtPose({300.0 * std::sin(t), 0.0, 300.0 * std::cos(t)}, {0, 0, 0}, {0, 1, 0});
}
inline Eigen::Vector3d stillLightMm() {
  const double t = 30.0 * M_PI / 180.0;
  return {-300.0 * std::sin(t) * 0.7, 300.0 * std::sin(t) * 0.7, 300.0 * std::cos(t)};
}

/// \brief A ModelCamera on a fake clock looking at a StillScene with the LED on throughout.
struct BracketRig {
  hal::FakeClock clock{1'000'000};
  std::shared_ptr<StillScene> scene;
  hal::SensorModel model;
  std::unique_ptr<hal::ModelCamera> camera;

  BracketRig(std::shared_ptr<StillScene> s, hal::SensorModel m) : scene(std::move(s)), model(m) {
    model.realTime = false;
    camera = std::make_unique<hal::ModelCamera>(scene, std::make_shared<hal::LedTimeline>(true),
                                                clock, model);
    hal::CameraConfig config;
    camera->configure(config);
    camera->start();
  }

  /// \brief The exposure (us, at unit gain) that puts the brightest 0.5 % of the pixels' largest
  /// channel, after the colour gains, at 0.35 of full scale: what the daemon's metering does.
  double meteredExposureUs() const {
    const hal::SceneLight& l = scene->light();
    std::vector<double> levels;
    for (std::size_t p = 0; p + 2 < l.ledRate.size(); p += 3) {
      double largest = 0.0;
      for (int c = 0; c < 3; ++c)
        largest = std::max(largest, (l.ledRate[p + c] + double(l.ambientRate[p + c])) *
                                        model.colourGains[c]);
      levels.push_back(largest);
    }
    const auto rank = levels.begin() + std::ptrdiff_t(0.995 * double(levels.size() - 1));
    std::nth_element(levels.begin(), rank, levels.end());
    return 0.35 / *rank * 1e6;
  }

  /// \brief One frame at each setting: the first frame taken under its lock.
  std::vector<hal::Frame> take(const std::vector<hal::ExposureSetting>& settings) {
    std::vector<hal::Frame> frames;
    for (const hal::ExposureSetting& setting : settings) {
      const std::uint32_t locks = frames.empty() ? 1u : frames.back().metadata.exposureLocks + 1;
      if (!camera->lockExposure(setting).locked) throw std::runtime_error("lock refused");
      for (int n = 0;; ++n) {
        hal::CaptureResult result = camera->nextFrame(std::chrono::milliseconds(1000));
        if (result.status != hal::CaptureResult::Status::Frame || n > 20)
          throw std::runtime_error("the model camera gave no frame under lock " +
                                   std::to_string(locks));
        if (result.frame->metadata.exposureLocks >= locks) {
          frames.push_back(std::move(*result.frame));
          break;
        }
      }
    }
    return frames;
  }
};

}  // namespace slicecap::test
