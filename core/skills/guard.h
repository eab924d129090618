// Guard mode (issue 22, intruder detection): while on, a thread watches through the robot's
// camera where it faces (a door, by default; with `turn_deg` it also turns in place a stop at a
// time, but then "I'm home" may find it facing away); a face nobody enrolled, big enough to
// identify (`min_face_px`), seen in `frames_needed` consecutive looks is an intruder: the alert
// callback gets a photo taken then (it says so, logs the event, publishes it). A still picture
// of a person on a TV is set aside (`is_picture`): a face inside a box the detector labels a
// screen ("tv", "laptop"), or one the map puts at a screen (GoingPlaces::screen_at); a poster
// the map does not know still alerts. Requiring several frames removes one-frame
// misdetections. Known faces never alert.
//
// On/off: on() from anyone; off() is the host API's job to allow only for a known face in view
// (finding_api.cpp, `guard`). Another process (`marvin guard off`) turns it off through
// `off_requested`, asked before every look; `changed` hears every change (the host keeps the
// state in SQLite for `marvin guard status`). Thread-safe.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
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
  int pictures = 0;           // looks since then that saw faces of pictures only (a TV)
};

struct GuardOptions {
  int frames_needed = 3;                // consecutive looks with an unknown face
  std::chrono::milliseconds look{250};  // robot time between looks
  int looks_per_stop = 4;               // then turn `turn_deg` (0: never turn)
  double turn_deg = 0;
  // A face smaller than this (pixels high) is too far to tell known from unknown: a known
  // face across the room is often not recognised, and must not raise an alarm.
  double min_face_px = 40;
  double time_scale = 1;  // robot seconds per wall second
  bool watch = true;      // false: state only, no thread (the MockRobot)
  // Optional. Told every change (on, off, an alert, the end of the program while on), on the
  // caller's or the guard's thread, never under the guard's lock.
  std::function<void(const GuardState&)> changed;
  // Optional. Asked before every look while on; true turns the guard off, `by` becoming
  // kOffByCommandLine (the watch ends; the next on() starts a new one).
  std::function<bool(const GuardState&)> off_requested;
};

// GuardState::by when `off_requested` turned it off, and when the program ended while on.
inline constexpr const char* kOffByCommandLine = "the command line";
inline constexpr const char* kOffByShutdown = "Marvin shutting down";

// Where the host keeps the guard's state for other processes: the storage table under this
// reserved skill id ("host." is no skill's), keys kGuardStateKey (the state as JSON, written at
// every change) and kGuardOffKey (`marvin guard off`: the since_unix_ms of the watch to end,
// so a request never ends a later watch).
inline constexpr const char* kGuardStorageId = "host.guard";
inline constexpr const char* kGuardStateKey = "state";
inline constexpr const char* kGuardOffKey = "off_request";

// {"on", "since_unix_ms", "alerts", "by", "pictures"} and back (a field missing or of the
// wrong type: std::invalid_argument naming it; "pictures" may be missing: state stored before
// session 9).
std::string guard_state_json(const GuardState& s);
GuardState guard_state_from_json(const std::string& text);

// Whether `face` (an entry of Eyes::look_json's "faces") of the look `seen` is a picture of a
// person rather than a person: inside an object box the detector labels "tv" or "laptop", or
// (with `places`) at a screen on the map by its bearing and the distance its size gives.
bool is_picture(const nlohmann::json& face, const nlohmann::json& seen,
                navigation::GoingPlaces* places);

class Guard {
 public:
  // `alert(photo_path, message)` runs on the guard's thread; `now_ms` is Unix ms. `places`
  // may be null (then the guard never turns).
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
  void tell(const GuardState& s);                 // options_.changed, its exceptions logged
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
