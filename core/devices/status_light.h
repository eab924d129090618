// The head's status LEDs (74HC595 on the MCU): red awaiting, green listening, yellow
// executing.
#pragma once

#include <cstdint>
#include <mutex>

#include "devices/body.h"
#include "devices/serial_link.h"

namespace marvin::devices {

// Thread-safe. The light is remembered and sent again after a reconnect (resend()).
class StatusLight {
 public:
  explicit StatusLight(SerialLink& link) : link_(link) {}
  void set(Light light);
  Light light() const;
  void resend();
  // The LED bits (MV_LED_*) for a light.
  static std::uint8_t bits(Light light);

 private:
  SerialLink& link_;
  mutable std::mutex mu_;
  Light light_ = Light::kOff;
};

}  // namespace marvin::devices
