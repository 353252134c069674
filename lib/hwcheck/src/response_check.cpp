// Response curve check: meter, bracket, fit, and compare with linear and sRGB.
#include "slicecap/hwcheck/response_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "slicecap/hwcheck/hardware_check_error.hpp"

namespace slicecap::hwcheck {

double curveDistance(const ToneCurve& a, const ToneCurve& b, double lowCode, double highCode,
                     double referenceCode) {
  const double aRef = a.decode(referenceCode / 255.0), bRef = b.decode(referenceCode / 255.0);
  double worst = 0.0;
  for (double code = std::ceil(lowCode); code <= highCode; code += 1.0) {
    const double ra = a.decode(code / 255.0) / aRef, rb = b.decode(code / 255.0) / bRef;
    if (rb > 0.0) worst = std::max(worst, std::abs(ra / rb - 1.0));
  }
  return worst;
}

namespace {

// The code of the brightest 0.5 % of the frame's pixels, largest channel (the daemon's metering
// looks at the same statistic).
int brightCode(const hal::Frame& frame) {
  std::array<std::size_t, 256> histogram{};
  const auto& s = frame.image.samples;
  const int channels = std::max(frame.image.channels, 1);
  std::size_t pixels = 0;
  for (std::size_t i = 0; i + std::size_t(channels) <= s.size(); i += std::size_t(channels), ++pixels) {
    std::uint16_t largest = 0;
    for (int c = 0; c < channels; ++c) largest = std::max(largest, s[i + std::size_t(c)]);
    ++histogram[std::min<std::uint16_t>(largest, 255)];
  }
  std::size_t above = 0;
  for (int code = 255; code >= 0; --code) {
    above += histogram[std::size_t(code)];
    if (double(above) >= 0.005 * double(pixels)) return code;
  }
  return 0;
}

}  // namespace

ResponseCheck checkResponse(CheckRig& rig, const vision::TargetGeometry& target,
                            const vision::CameraModel& camera, const capture::BracketPlan& plan) {
  ResponseCheck check;
  // Metering: aim the bright end at code 160 (about 0.35 of linear full scale on sRGB-like and
  // ISP curves), by the sRGB curve since the camera's own is not known yet; the bracket's 128 x
  // range forgives an error of a stop or two.
  std::optional<SeenFrame> frame = rig.next(std::chrono::milliseconds(1000));
  if (!frame) throw HardwareCheckError(rig.camera().id() + ": no frame for a second");
  double exposureUs = frame->frame.metadata.exposureUs > 0 ? frame->frame.metadata.exposureUs : 10000.0;
  const ToneCurve srgb = ToneCurve::srgb();
  for (int step = 0; step < 4; ++step) {
    const int code = brightCode(frame->frame);
    if (code >= 150 && code <= 175) break;
    const double level = srgb.decode(std::max(code, 2) / 255.0);
    const double factor = std::clamp(srgb.decode(160.0 / 255.0) / level, 1.0 / 16, 16.0);
    exposureUs = std::clamp(exposureUs * (code >= 254 ? 0.25 : factor), 20.0, 33'000.0);
    try {
      frame = rig.lockAndWait({exposureUs, std::nullopt});
    } catch (const std::exception& error) {
      check.error = error.what();
      return check;
    }
    exposureUs = frame->frame.metadata.exposureUs > 0 ? frame->frame.metadata.exposureUs : exposureUs;
  }
  check.meteredExposureUs = exposureUs;
  std::vector<hal::Frame> bracket;
  try {
    for (const hal::ExposureSetting& setting : plan.settings({exposureUs, std::nullopt}))
      bracket.push_back(rig.lockAndWait(setting).frame);
    capture::ResponseFitParams params;
    params.cameraName = rig.camera().id();
    check.fit = capture::fitResponse(bracket, target, camera, params);
  } catch (const std::exception& error) {
    check.error = error.what();
    return check;
  }
  const double low = check.fit->lowestCode, high = check.fit->highestCode;
  check.fromLinear = curveDistance(check.fit->curve, ToneCurve::linear(), low, high, high);
  check.fromSrgb = curveDistance(check.fit->curve, srgb, low, high, high);
  return check;
}

CheckItem responseItem(const ResponseCheck& check, const std::string& cameraId) {
  CheckItem item{"response curve", Verdict::Ok, "", ""};
  if (!check.fit) {
    item.verdict = Verdict::Fail;
    item.finding = "no curve: " + check.error;
    item.advice = "put the whole target under the camera with the LED on, in a steady light; " +
                  cameraId + "'s frames are otherwise decoded as sRGB, which is wrong for most ISPs";
    return item;
  }
  char text[320];
  std::snprintf(text, sizeof text,
                "measured around %.0f us: %s; ratios to white differ from linear by up to %.1f %% "
                "and from sRGB by up to %.1f %%",
                check.meteredExposureUs, check.fit->summary().c_str(), 100.0 * *check.fromLinear,
                100.0 * *check.fromSrgb);
  item.finding = text;
  if (*check.fromSrgb > 0.05) {
    item.verdict = Verdict::Warn;
    item.advice = "the camera's frames are not sRGB: samples decoded as sRGB are wrong by up to "
                  "that much; use the RAW stream where the camera has one, else the measured curve "
                  "(docs/linear-light.md)";
  }
  return item;
}

}  // namespace slicecap::hwcheck
