// The 4-wheel base (two sides through the L293D), driven over the serial link.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
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
  // The MCU's deadman time: the wheels stop this long after the last valid frame. The
  // firmware's default (mv_config_defaults); the host never sends CONFIG to change it.
  static constexpr std::chrono::milliseconds kDeadman{300};

  // What the wheels were told, as it went out: locomotion frames for `direction` at `speed`
  // (a drive's first frames and each refresh), or speed 0: STOP_ALL was sent or the MCU
  // reported it stopped the wheels itself. A drive the host stops refreshing (it stalled, or
  // the link went down) ends kDeadman after its last frames, with no command of its own.
  struct WheelCommand {
    std::chrono::steady_clock::time_point at;
    Direction direction = Direction::kForward;
    std::uint8_t speed = 0;
  };
  using Observer = std::function<void(const WheelCommand&)>;

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
  // Ends the drive without a frame: the link is down, or the MCU's deadman stopped the wheels.
  void forget();
  // Ends the drive without a frame because the MCU stopped the wheels just now (an obstacle);
  // the observer is told speed 0.
  void stopped_by_mcu();
  bool driving() const;

  // Called with each WheelCommand as it goes out, in order, under the base's lock (so it must
  // not call back into MotorBase). One observer; an empty function removes it.
  void set_observer(Observer observer);

  // The two locomotion frames (direction codes) for a direction: {left, right}.
  static std::pair<std::uint8_t, std::uint8_t> wheel_codes(Direction direction);

 private:
  void run();
  void send_frames();
  void send_stop();
  void tell(std::uint8_t speed);

  SerialLink& link_;
  const std::chrono::milliseconds refresh_;
  mutable std::mutex mu_;
  std::condition_variable wake_;
  bool driving_ = false, quit_ = false;
  Direction direction_ = Direction::kForward;
  std::uint8_t speed_ = 0;
  std::chrono::steady_clock::time_point deadline_;
  std::uint64_t generation_ = 0;
  Observer observer_;
  std::thread thread_;
};

}  // namespace marvin::devices
