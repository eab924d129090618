// The 4-wheel base (two sides through the L293D), driven over the serial link.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "devices/body.h"
#include "devices/serial_link.h"

namespace marvin::devices {

// Drives for a duration. The MCU stops the motors when no valid command came for its
// deadman time (300 ms), so while a drive lasts MotorBase repeats the locomotion frames
// every `refresh` (default 100 ms) from its own thread, and sends STOP_ALL when the drive
// ends. Thread-safe.
class MotorBase {
 public:
  explicit MotorBase(SerialLink& link,
                     std::chrono::milliseconds refresh = std::chrono::milliseconds(100));
  // Stops the motors and the refresh thread.
  ~MotorBase();
  MotorBase(const MotorBase&) = delete;
  MotorBase& operator=(const MotorBase&) = delete;

  // Starts (or replaces) a drive; returns at once. Left/right turn in place.
  void drive(Direction direction, std::uint8_t speed, std::chrono::milliseconds duration);
  // Ends the drive and sends STOP_ALL.
  void stop();
  // Ends the drive without a frame (the MCU already stopped: obstacle, link lost).
  void forget();
  bool driving() const;

  // The two locomotion frames (direction codes) for a direction: {left, right}.
  static std::pair<std::uint8_t, std::uint8_t> wheel_codes(Direction direction);

 private:
  void run();
  void send_frames();

  SerialLink& link_;
  const std::chrono::milliseconds refresh_;
  mutable std::mutex mu_;
  std::condition_variable wake_;
  bool driving_ = false, quit_ = false;
  Direction direction_ = Direction::kForward;
  std::uint8_t speed_ = 0;
  std::chrono::steady_clock::time_point deadline_;
  std::uint64_t generation_ = 0;
  std::thread thread_;
};

}  // namespace marvin::devices
