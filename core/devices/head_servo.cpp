// The head. See head_servo.h.
#include "devices/head_servo.h"

#include <algorithm>

namespace marvin::devices {

int HeadServo::tilt(int degrees) {
  std::lock_guard lock(mu_);
  angle_ = std::clamp(degrees, kMinDeg, kMaxDeg);
  link_.send_ext(MV_HEAD_TILT, {static_cast<std::uint8_t>(angle_ + 64)});
  return angle_;
}

int HeadServo::angle() const {
  std::lock_guard lock(mu_);
  return angle_;
}

void HeadServo::resend() {
  std::lock_guard lock(mu_);
  link_.send_ext(MV_HEAD_TILT, {static_cast<std::uint8_t>(angle_ + 64)});
}

}  // namespace marvin::devices
