// Formatting of the hardware check's report.
#include "slicecap/hwcheck/check_report.hpp"

#include <algorithm>
#include <sstream>

namespace slicecap::hwcheck {

const char* toString(Verdict verdict) {
  switch (verdict) {
    case Verdict::Ok: return "ok";
    case Verdict::Warn: return "warn";
    case Verdict::Fail: return "fail";
  }
  return "fail";
}

Verdict HardwareReport::overall() const {
  Verdict worst = Verdict::Ok;
  for (const CheckItem& item : items) worst = std::max(worst, item.verdict);
  return worst;
}

std::string HardwareReport::configSnippet() const {
  std::ostringstream out;
  out << "# Measured by slicecapd --check-hardware on " << cameraId << "\n";
  for (const auto& [key, value] : configLines) out << key << " = " << value << "\n";
  return out.str();
}

std::string HardwareReport::text() const {
  std::ostringstream out;
  out << "camera: " << cameraId << "\n";
  for (const std::string& camera : cameras) out << "  found: " << camera << "\n";
  for (const CheckItem& item : items) {
    out << "[" << toString(item.verdict) << "] " << item.name << ": " << item.finding << "\n";
    if (!item.advice.empty()) out << "       what to do: " << item.advice << "\n";
  }
  out << "overall: " << toString(overall()) << "\n";
  if (!configLines.empty()) out << "\nconfiguration (slicecapd.conf):\n" << configSnippet();
  return out.str();
}

nlohmann::json HardwareReport::json() const {
  nlohmann::json items_ = nlohmann::json::array();
  for (const CheckItem& item : items)
    items_.push_back({{"name", item.name},
                      {"verdict", toString(item.verdict)},
                      {"finding", item.finding},
                      {"advice", item.advice}});
  nlohmann::json figures_ = nlohmann::json::object();
  const auto put = [&figures_](const char* key, const auto& value) {
    if (value) figures_[key] = *value;
  };
  put("frame_period_us", figures.framePeriodUs);
  put("frame_jitter_us", figures.frameJitterUs);
  put("frames_dropped", figures.framesDropped);
  put("frames_seen", figures.framesSeen);
  put("exposure_lock_delay_frames", figures.exposureLockDelayFrames);
  put("line_time_us", figures.lineTimeUs);
  put("readout_us", figures.readoutUs);
  put("sensor_read_noise", figures.sensorReadNoise);
  put("sensor_full_well_electrons", figures.sensorFullWellElectrons);
  put("led_offset_us", figures.ledOffsetUs);
  put("led_offset_spread_us", figures.ledOffsetSpreadUs);
  put("delivery_latency_us", figures.deliveryLatencyUs);
  put("curve_from_linear", figures.curveFromLinear);
  put("curve_from_srgb", figures.curveFromSrgb);
  put("flicker_hz", figures.flickerHz);
  put("flicker_depth", figures.flickerDepth);
  put("room_to_led", figures.roomToLed);
  nlohmann::json config = nlohmann::json::object();
  for (const auto& [key, value] : configLines) config[key] = value;
  return {{"camera", cameraId}, {"cameras", cameras},          {"overall", toString(overall())},
          {"items", items_},    {"figures", figures_},         {"config", config}};
}

}  // namespace slicecap::hwcheck
