// The wheels. See motor_base.h.
#include "devices/motor_base.h"

namespace marvin::devices {

MotorBase::MotorBase(SerialLink& link, std::chrono::milliseconds refresh)
    : link_(link), refresh_(refresh), thread_([this] { run(); }) {}

MotorBase::~MotorBase() {
  stop();
  {
    std::lock_guard lock(mu_);
    quit_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::pair<std::uint8_t, std::uint8_t> MotorBase::wheel_codes(Direction direction) {
  switch (direction) {
    case Direction::kForward:
      return {MV_LEFT_FORWARD, MV_RIGHT_FORWARD};
    case Direction::kBackward:
      return {MV_LEFT_BACKWARD, MV_RIGHT_BACKWARD};
    case Direction::kLeft:
      return {MV_LEFT_BACKWARD, MV_RIGHT_FORWARD};
    case Direction::kRight:
      return {MV_LEFT_FORWARD, MV_RIGHT_BACKWARD};
  }
  return {MV_LEFT_FORWARD, MV_RIGHT_FORWARD};
}

// The helpers below run under mu_.
void MotorBase::tell(std::uint8_t speed) {
  if (observer_) observer_({std::chrono::steady_clock::now(), direction_, speed});
}

void MotorBase::send_frames() {
  auto [left, right] = wheel_codes(direction_);
  const bool sent = link_.send_locomotion(left, speed_);
  if (link_.send_locomotion(right, speed_) && sent) tell(speed_);
}

void MotorBase::send_stop() {
  if (link_.send_ext(MV_STOP_ALL, {})) tell(0);
}

void MotorBase::drive(Direction direction, std::uint8_t speed, std::chrono::milliseconds duration) {
  {
    std::lock_guard lock(mu_);
    direction_ = direction;
    speed_ = speed;
    deadline_ = std::chrono::steady_clock::now() + duration;
    driving_ = speed != 0 && duration.count() > 0;
    ++generation_;
    if (driving_) {
      send_frames();
    } else {
      send_stop();
    }
  }
  wake_.notify_all();
}

void MotorBase::stop() {
  {
    std::lock_guard lock(mu_);
    driving_ = false;
    ++generation_;
    send_stop();
  }
  wake_.notify_all();
}

void MotorBase::forget() {
  {
    std::lock_guard lock(mu_);
    driving_ = false;
    ++generation_;
  }
  wake_.notify_all();
}

void MotorBase::stopped_by_mcu() {
  {
    std::lock_guard lock(mu_);
    driving_ = false;
    ++generation_;
    tell(0);
  }
  wake_.notify_all();
}

void MotorBase::set_observer(Observer observer) {
  std::lock_guard lock(mu_);
  observer_ = std::move(observer);
}

bool MotorBase::driving() const {
  std::lock_guard lock(mu_);
  return driving_;
}

void MotorBase::run() {
  std::unique_lock lock(mu_);
  while (!quit_) {
    if (!driving_) {
      wake_.wait(lock);
      continue;
    }
    std::uint64_t generation = generation_;
    auto next = std::min(std::chrono::steady_clock::now() + refresh_, deadline_);
    wake_.wait_until(lock, next, [&] { return quit_ || generation_ != generation; });
    if (quit_ || generation_ != generation || !driving_) continue;
    if (std::chrono::steady_clock::now() >= deadline_) {
      driving_ = false;
      send_stop();
    } else {
      send_frames();
    }
  }
}

}  // namespace marvin::devices
