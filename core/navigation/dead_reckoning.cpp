#include "navigation/dead_reckoning.h"

#include <algorithm>
#include <cmath>

#include "devices/motor_base.h"

namespace marvin::navigation {

DeadReckoning::DeadReckoning(devices::Body& base, BaseSpec spec, Pose start,
                             std::function<bool()> still_moving, Clock clock)
    : base_(base),
      spec_(spec),
      still_moving_(std::move(still_moving)),
      clock_(clock ? std::move(clock) : Clock([] { return std::chrono::steady_clock::now(); })),
      pose_(start) {
  last_ = until_ = clock_();
}

void DeadReckoning::advance_locked(std::chrono::steady_clock::time_point now) {
  if (still_moving_ && !still_moving_()) target_[0] = target_[1] = 0;  // the base stopped
  auto integrate = [this](double seconds) {
    const double step = 0.005;
    while (seconds > 1e-9) {
      const double dt = std::min(step, seconds);
      seconds -= dt;
      const double dv = spec_.accel_m_s2 * dt;
      for (int s = 0; s < 2; ++s) v_[s] += std::clamp(target_[s] - v_[s], -dv, dv);
      const double v = (v_[0] + v_[1]) / 2, w = (v_[1] - v_[0]) / spec_.track_m;
      const double mid = pose_.heading + w * dt / 2;
      pose_.x += v * dt * std::cos(mid);
      pose_.y += v * dt * std::sin(mid);
      pose_.heading = wrap_angle(pose_.heading + w * dt);
    }
  };
  if (now <= last_) return;
  // The timed move ends at until_: driven up to then, coasting to a stop after.
  if (until_ > last_ && until_ < now) {
    integrate(std::chrono::duration<double>(until_ - last_).count());
    last_ = until_;
  }
  if (now >= until_) target_[0] = target_[1] = 0;
  integrate(std::chrono::duration<double>(now - last_).count());
  last_ = now;
}

void DeadReckoning::move(devices::Direction direction, std::uint8_t speed,
                         std::chrono::milliseconds duration) {
  {
    std::lock_guard lock(mu_);
    const auto now = clock_();
    advance_locked(now);
    // The same two locomotion frames the serial body sends: code 0 LF, 1 LB, 2 RF, 3 RB.
    const auto [l, r] = devices::MotorBase::wheel_codes(direction);
    for (std::uint8_t code : {l, r}) {
      const double v = speed / 255.0 * spec_.max_speed_m_s;
      target_[code >> 1] = (code & 1) ? -v : v;
    }
    until_ = now + duration;
  }
  base_.move(direction, speed, duration);
}

void DeadReckoning::stop() {
  {
    std::lock_guard lock(mu_);
    advance_locked(clock_());
    target_[0] = target_[1] = 0;
    until_ = last_;
  }
  base_.stop();
}

Pose DeadReckoning::pose() {
  std::lock_guard lock(mu_);
  advance_locked(clock_());
  return pose_;
}

}  // namespace marvin::navigation
