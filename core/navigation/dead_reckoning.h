// Dead reckoning for a base without wheel encoders (the real robot today): a Body in front
// of the real one that integrates what the wheels were told — each side's commanded speed,
// reached at the base's acceleration, over the steady clock — into a pose the Navigator can
// use. Its error grows with distance and turns (README.md: limits). Thread-safe.
//
// On the serial base it integrates the wheel commands as they go out (MotorBase's observer),
// not the moves asked of it: a drive lasts while its frames keep coming and ends
// MotorBase::kDeadman after the last, as the MCU's deadman ends it. So when the host stalls
// longer than that (a busy machine), the pose still follows the body, which stopped, and
// not the move that was asked for, which would have gone on.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>

#include "devices/body.h"
#include "devices/motor_base.h"
#include "navigation/geometry.h"

namespace marvin::navigation {

struct BaseSpec {
  double max_speed_m_s = 0.4;  // a side at speed 255
  double track_m = 0.25;
  double accel_m_s2 = 1.0;
};

class DeadReckoning : public devices::Body {
 public:
  using Clock = std::function<std::chrono::steady_clock::time_point()>;
  // Integrates the moves and stops passed on to `base`: each move drives for as long as asked.
  DeadReckoning(devices::Body& base, BaseSpec spec, Pose start, Clock clock = {});
  // The serial base: `base` (its SerialBody) gets the moves, and the pose integrates the wheel
  // commands `motors` reports. Both must outlive this.
  DeadReckoning(devices::Body& base, devices::MotorBase& motors, BaseSpec spec, Pose start);
  ~DeadReckoning() override;
  DeadReckoning(const DeadReckoning&) = delete;
  DeadReckoning& operator=(const DeadReckoning&) = delete;

  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override { base_.tilt_head(degrees); }
  std::vector<devices::ScanPoint> latest_scan() override { return base_.latest_scan(); }
  void set_light(devices::Light light) override { base_.set_light(light); }

  // The pose as of now.
  Pose pose();

  // Integrates one wheel command, which holds until `holds_for` after it unless another comes
  // first. The serial form is fed these by MotorBase; public so that a test can feed them on
  // a clock of its own (with the first form, and then not mixed with move()).
  void wheel_command(const devices::MotorBase::WheelCommand& command,
                     std::chrono::milliseconds holds_for);

 private:
  void advance_locked(std::chrono::steady_clock::time_point now);
  void set_target_locked(devices::Direction direction, std::uint8_t speed);

  devices::Body& base_;
  devices::MotorBase* motors_ = nullptr;  // the serial form: integrates its wheel commands
  const BaseSpec spec_;
  Clock clock_;
  std::mutex mu_;
  Pose pose_;
  double target_[2] = {0, 0}, v_[2] = {0, 0};
  std::chrono::steady_clock::time_point last_, until_;
};

}  // namespace marvin::navigation
