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

void MotorBase::send_frames() {
  auto [left, right] = wheel_codes(direction_);
  link_.send_locomotion(left, speed_);
  link_.send_locomotion(right, speed_);
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
      link_.send_ext(MV_STOP_ALL, {});
    }
  }
  wake_.notify_all();
}

void MotorBase::stop() {
  {
    std::lock_guard lock(mu_);
    driving_ = false;
    ++generation_;
    link_.send_ext(MV_STOP_ALL, {});
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
      link_.send_ext(MV_STOP_ALL, {});
    } else {
      send_frames();
    }
  }
}

}  // namespace marvin::devices
