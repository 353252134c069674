// GpiodLed on libgpiod 2.x (newer distributions; selected with -DSLICECAP_GPIOD_V2=ON): chips
// are opened by path, lines are requests with settings. scripts/check-gpiod-v2 compiles this file
// against the 2.x header, since Debian 12 has no 2.x package.
#include <gpiod.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "gpiod_led_common.hpp"

namespace slicecap::hal {
namespace {

using gpiod_detail::chipPath;
using gpiod_detail::fail;
using gpiod_detail::lineLabel;

/// \brief /dev/gpiochip* in numeric order, for a line given by name and no chip.
std::vector<std::string> allChipPaths() {
  std::vector<std::string> paths;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/dev", error)) {
    const std::string path = entry.path().string();
    if (gpiod_is_gpiochip_device(path.c_str())) paths.push_back(path);
  }
  std::sort(paths.begin(), paths.end(), [](const std::string& a, const std::string& b) {
    return a.size() != b.size() ? a.size() < b.size() : a < b;
  });
  return paths;
}

class GpiodV2Line final : public detail::GpioOutputLine {
 public:
  explicit GpiodV2Line(const GpioLineSpec& spec) : label_(lineLabel(spec)) {
    const std::optional<unsigned> offset = gpioLineOffset(spec.line);
    if (offset && spec.chip.empty())
      throw GpioError(label_ + ": a line given by offset needs led_chip (e.g. gpiochip0)");
    const std::vector<std::string> candidates =
        spec.chip.empty() ? allChipPaths() : std::vector<std::string>{chipPath(spec.chip)};
    for (const std::string& path : candidates) {
      gpiod_chip* chip = gpiod_chip_open(path.c_str());
      if (chip == nullptr) {
        if (!spec.chip.empty()) fail(label_ + ": cannot open the chip", errno);
        continue;
      }
      const int found = offset ? static_cast<int>(*offset)
                               : gpiod_chip_get_line_offset_from_name(chip, spec.line.c_str());
      if (found >= 0) {
        chip_ = chip;
        offset_ = static_cast<unsigned>(found);
        where_ = path.substr(path.rfind('/') + 1) + ":" + std::to_string(offset_);
        if (!offset) where_ += " (" + spec.line + ")";
        break;
      }
      gpiod_chip_close(chip);
    }
    if (chip_ == nullptr)
      throw GpioError(label_ + ": no line of that name (gpioinfo lists the lines)");
    request(spec.activeLow);
  }

  ~GpiodV2Line() override {
    if (request_ != nullptr) {
      gpiod_line_request_set_value(request_, offset_, GPIOD_LINE_VALUE_INACTIVE);
      gpiod_line_request_release(request_);
    }
    gpiod_chip_close(chip_);
  }

  void setActive(bool active) override {
    if (gpiod_line_request_set_value(
            request_, offset_, active ? GPIOD_LINE_VALUE_ACTIVE : GPIOD_LINE_VALUE_INACTIVE) != 0)
      fail(where_ + ": cannot switch the LED " + (active ? "on" : "off"), errno);
  }

  std::string where() const override { return where_; }

 private:
  void request(bool activeLow) {
    gpiod_line_settings* settings = gpiod_line_settings_new();
    gpiod_line_config* lineConfig = gpiod_line_config_new();
    gpiod_request_config* requestConfig = gpiod_request_config_new();
    int error = ENOMEM;
    if (settings != nullptr && lineConfig != nullptr && requestConfig != nullptr) {
      gpiod_line_settings_set_direction(settings, GPIOD_LINE_DIRECTION_OUTPUT);
      gpiod_line_settings_set_active_low(settings, activeLow);
      gpiod_line_settings_set_output_value(settings, GPIOD_LINE_VALUE_INACTIVE);
      gpiod_request_config_set_consumer(requestConfig, gpiod_detail::kConsumer);
      if (gpiod_line_config_add_line_settings(lineConfig, &offset_, 1, settings) == 0)
        request_ = gpiod_chip_request_lines(chip_, requestConfig, lineConfig);
      error = errno;
    }
    gpiod_request_config_free(requestConfig);
    gpiod_line_config_free(lineConfig);
    gpiod_line_settings_free(settings);
    if (request_ == nullptr) {
      gpiod_chip_close(chip_);
      chip_ = nullptr;
      fail(label_ + " (" + where_ + "): cannot request it as an output", error);
    }
  }

  std::string label_;
  std::string where_;
  gpiod_chip* chip_ = nullptr;
  gpiod_line_request* request_ = nullptr;
  unsigned offset_ = 0;
};

}  // namespace

std::unique_ptr<detail::GpioOutputLine> detail::openGpioOutputLine(const GpioLineSpec& spec) {
  return std::make_unique<GpiodV2Line>(spec);
}

}  // namespace slicecap::hal
