// An LED that only remembers its state: for tests whose light reaches the camera another way (the
// model camera's LedTimeline) or not at all.
#pragma once

#include <string>

#include "slicecap/hal/led.hpp"

namespace slicecap::test {

class PlainLed final : public hal::Led {
 public:
  std::string id() const override { return "plain"; }
  void set(bool on) override { on_ = on; }
  bool isOn() const override { return on_; }

 private:
  bool on_ = false;
};

}  // namespace slicecap::test
