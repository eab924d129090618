// The status light. See status_light.h.
#include "devices/status_light.h"

namespace marvin::devices {

std::uint8_t StatusLight::bits(Light light) {
  switch (light) {
    case Light::kOff:
      return 0;
    case Light::kAwaiting:
      return MV_LED_RED;
    case Light::kListening:
      return MV_LED_GREEN;
    case Light::kExecuting:
      return MV_LED_YELLOW;
  }
  return 0;
}

void StatusLight::set(Light light) {
  std::lock_guard lock(mu_);
  light_ = light;
  link_.send_ext(MV_LEDS, {bits(light)});
}

Light StatusLight::light() const {
  std::lock_guard lock(mu_);
  return light_;
}

void StatusLight::resend() {
  std::lock_guard lock(mu_);
  link_.send_ext(MV_LEDS, {bits(light_)});
}

}  // namespace marvin::devices
