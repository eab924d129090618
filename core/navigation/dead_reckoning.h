// Dead reckoning for a base without wheel encoders (the real robot today): a Body in front
// of the real one that integrates the commands it passes on — each side's commanded speed,
// reached at the base's acceleration, over the steady clock — into a pose the Navigator can
// use. It knows a move ended early only through `still_moving` (the serial body's
// MotorBase::driving(): the MCU stopped for an obstacle or a lost link). Its error grows with
// distance and turns (README.md: limits). Thread-safe.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>

#include "devices/body.h"
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
  DeadReckoning(devices::Body& base, BaseSpec spec, Pose start,
                std::function<bool()> still_moving = {}, Clock clock = {});

  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override { base_.tilt_head(degrees); }
  std::vector<devices::ScanPoint> latest_scan() override { return base_.latest_scan(); }
  void set_light(devices::Light light) override { base_.set_light(light); }

  // The pose as of now.
  Pose pose();

 private:
  void advance_locked(std::chrono::steady_clock::time_point now);

  devices::Body& base_;
  const BaseSpec spec_;
  std::function<bool()> still_moving_;
  Clock clock_;
  std::mutex mu_;
  Pose pose_;
  double target_[2] = {0, 0}, v_[2] = {0, 0};
  std::chrono::steady_clock::time_point last_, until_;
};

}  // namespace marvin::navigation
