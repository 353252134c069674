// GpiodLed on libgpiod 1.x (Debian 12 and Raspberry Pi OS bookworm ship 1.6): the v1 API of
// gpiod_line handles, which 2.x removed.
#include <gpiod.h>

#include "gpiod_led_common.hpp"

namespace slicecap::hal {
namespace {

using gpiod_detail::fail;
using gpiod_detail::lineLabel;

class GpiodV1Line final : public detail::GpioOutputLine {
 public:
  explicit GpiodV1Line(const GpioLineSpec& spec) : label_(lineLabel(spec)) {
    const std::optional<unsigned> offset = gpioLineOffset(spec.line);
    if (offset && spec.chip.empty())
      throw GpioError(label_ + ": a line given by offset needs led_chip (e.g. gpiochip0)");
    if (spec.chip.empty()) {
      errno = 0;
      line_ = gpiod_line_find(spec.line.c_str());
      if (line_ == nullptr) {
        if (errno == 0 || errno == ENOENT)
          throw GpioError(label_ + ": no line of that name (gpioinfo lists the lines)");
        fail(label_ + ": cannot search the GPIO chips", errno);
      }
      chip_ = gpiod_line_get_chip(line_);
      ownsChipThroughLine_ = true;
    } else {
      chip_ = gpiod_chip_open_lookup(spec.chip.c_str());
      if (chip_ == nullptr) fail(label_ + ": cannot open the chip", errno);
      line_ = offset ? gpiod_chip_get_line(chip_, *offset)
                     : gpiod_chip_find_line(chip_, spec.line.c_str());
      if (line_ == nullptr) {
        gpiod_chip_close(chip_);
        throw GpioError(label_ + ": the chip has no such line");
      }
    }
    const int flags = spec.activeLow ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
    if (gpiod_line_request_output_flags(line_, gpiod_detail::kConsumer, flags, 0) != 0) {
      const int error = errno;
      const char* holder = gpiod_line_consumer(line_);
      const std::string who = holder != nullptr ? std::string(" (held by '") + holder + "')" : "";
      closeChip();
      fail(label_ + ": cannot request it as an output" + who, error);
    }
    where_ = std::string(gpiod_chip_name(chip_)) + ":" + std::to_string(gpiod_line_offset(line_));
    if (const char* name = gpiod_line_name(line_); name != nullptr)
      where_ += std::string(" (") + name + ")";
  }

  ~GpiodV1Line() override {
    gpiod_line_set_value(line_, 0);
    gpiod_line_release(line_);
    closeChip();
  }

  void setActive(bool active) override {
    if (gpiod_line_set_value(line_, active ? 1 : 0) != 0)
      fail(where_ + ": cannot switch the LED " + (active ? "on" : "off"), errno);
  }

  std::string where() const override { return where_; }

 private:
  void closeChip() {
    if (ownsChipThroughLine_)
      gpiod_line_close_chip(line_);
    else
      gpiod_chip_close(chip_);
  }

  std::string label_;
  std::string where_;
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
  bool ownsChipThroughLine_ = false;
};

}  // namespace

std::unique_ptr<detail::GpioOutputLine> detail::openGpioOutputLine(const GpioLineSpec& spec) {
  return std::make_unique<GpiodV1Line>(spec);
}

}  // namespace slicecap::hal
