// Guard mode (issue 22, intruder detection): while on, a thread watches through the
// robot's camera where it faces (a door, by default; with `turn_deg` it also turns in place a
// stop at a time, but then "I'm home" may find it facing away); a face nobody enrolled, big
// enough to identify (`min_face_px`), seen in `frames_needed` consecutive looks is an intruder: the alert callback gets a
// photo taken then (it says so, logs the event, publishes it). A still picture of a person
// (a TV, a poster) is the false alarm this cannot tell apart yet; requiring several frames
// removes the one-frame misdetections only. Known faces never alert.
//
// On/off: on() from anyone; off() is the host API's job to allow only for a known face in
// view (host_api.cpp, `guard`), or from the CLI. Thread-safe.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "navigation/going_places.h"
#include "skills/eyes.h"

namespace marvin::skills {

struct GuardState {
  bool on = false;
  std::int64_t since_ms = 0;  // when it was turned on (Unix ms)
  int alerts = 0;             // alerts since then
  std::string by;             // who turned it off last
};

struct GuardOptions {
  int frames_needed = 3;               // consecutive looks with an unknown face
  std::chrono::milliseconds look{250}; // robot time between looks
  int looks_per_stop = 4;              // then turn `turn_deg` (0: never turn)
  double turn_deg = 0;
  // A face smaller than this (pixels high) is too far to tell known from unknown: a known
  // face across the room is often not recognised, and must not raise an alarm.
  double min_face_px = 40;
  double time_scale = 1;               // robot seconds per wall second
  bool watch = true;                   // false: state only, no thread (the MockRobot)
};

class Guard {
 public:
  // `alert(photo_path, message)` runs on the guard's thread; `now_ms` is Unix ms.
  // `places` may be null (then the guard never turns).
  Guard(Eyes& eyes, navigation::GoingPlaces* places, std::function<std::int64_t()> now_ms,
        std::function<void(const std::string& photo, const std::string& message)> alert,
        GuardOptions options = {});
  ~Guard();
  Guard(const Guard&) = delete;
  Guard& operator=(const Guard&) = delete;

  GuardState on();
  GuardState off(const std::string& by);
  GuardState state();

 private:
  void run();
  bool wait(std::chrono::milliseconds robot_ms);  // true when turned off meanwhile

  Eyes& eyes_;
  navigation::GoingPlaces* places_;
  std::function<std::int64_t()> now_ms_;
  std::function<void(const std::string&, const std::string&)> alert_;
  GuardOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  GuardState state_;
  bool quit_ = false;
  std::thread thread_;
};

}  // namespace marvin::skills
