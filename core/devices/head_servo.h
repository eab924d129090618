// The MG996R servo that tilts the head.
#pragma once

#include <mutex>

#include "devices/serial_link.h"

namespace marvin::devices {

// Thread-safe. The angle is remembered and sent again after a reconnect (resend()).
class HeadServo {
 public:
  static constexpr int kMinDeg = -60, kMaxDeg = 60;
  explicit HeadServo(SerialLink& link) : link_(link) {}
  // Tilts to `degrees` above level, clamped to kMinDeg..kMaxDeg. Returns the angle used.
  int tilt(int degrees);
  int angle() const;
  void resend();

 private:
  SerialLink& link_;
  mutable std::mutex mu_;
  int angle_ = 0;
};

}  // namespace marvin::devices
