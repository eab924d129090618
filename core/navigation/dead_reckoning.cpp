#include "navigation/dead_reckoning.h"

#include <algorithm>
#include <cmath>

#include "devices/motor_base.h"

namespace marvin::navigation {

DeadReckoning::DeadReckoning(devices::Body& base, BaseSpec spec, Pose start, Clock clock)
    : base_(base),
      spec_(spec),
      clock_(clock ? std::move(clock) : Clock([] { return std::chrono::steady_clock::now(); })),
      pose_(start) {
  last_ = until_ = clock_();
}

DeadReckoning::DeadReckoning(devices::Body& base, devices::MotorBase& motors, BaseSpec spec,
                             Pose start)
    : DeadReckoning(base, spec, start) {
  motors_ = &motors;
  motors.set_observer([this](const devices::MotorBase::WheelCommand& command) {
    wheel_command(command, devices::MotorBase::kDeadman);
  });
}

DeadReckoning::~DeadReckoning() {
  if (motors_) motors_->set_observer({});
}

void DeadReckoning::advance_locked(std::chrono::steady_clock::time_point now) {
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

void DeadReckoning::set_target_locked(devices::Direction direction, std::uint8_t speed) {
  // The same two locomotion frames the serial body sends: code 0 LF, 1 LB, 2 RF, 3 RB.
  const auto [l, r] = devices::MotorBase::wheel_codes(direction);
  for (std::uint8_t code : {l, r}) {
    const double v = speed / 255.0 * spec_.max_speed_m_s;
    target_[code >> 1] = (code & 1) ? -v : v;
  }
}

void DeadReckoning::move(devices::Direction direction, std::uint8_t speed,
                         std::chrono::milliseconds duration) {
  if (!motors_) {
    std::lock_guard lock(mu_);
    const auto now = clock_();
    advance_locked(now);
    set_target_locked(direction, speed);
    until_ = now + duration;
  }
  base_.move(direction, speed, duration);  // the serial form hears of it from the motors
}

void DeadReckoning::stop() {
  if (!motors_) {
    std::lock_guard lock(mu_);
    advance_locked(clock_());
    target_[0] = target_[1] = 0;
    until_ = last_;
  }
  base_.stop();
}

void DeadReckoning::wheel_command(const devices::MotorBase::WheelCommand& command,
                                  std::chrono::milliseconds holds_for) {
  std::lock_guard lock(mu_);
  // A pose() that took the clock just after the command was stamped may have integrated past
  // it already: the command then takes effect from there (microseconds late).
  const auto at = std::max(command.at, last_);
  advance_locked(at);
  set_target_locked(command.direction, command.speed);
  until_ = command.speed ? at + holds_for : at;
}

Pose DeadReckoning::pose() {
  std::lock_guard lock(mu_);
  advance_locked(clock_());
  return pose_;
}

}  // namespace marvin::navigation
