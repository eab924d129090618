// The host's implementation of the Robot API table (marvin/robot.h).
//
// Each skill instance gets its own SkillContext; its address is the marvin_host* the
// skill passes back on every call, so the host knows who is calling: which permissions
// the manifest grants, whose storage keys to use, which task to cancel. Calls the
// manifest does not grant fail with MARVIN_ERR_PERMISSION and a sentence naming the
// permission and the skill. Schedules, contacts, people and storage are served from
// PersonalData; light and motion go to the Body; say/ask to the User; the camera to Eyes;
// going places to the navigator; smart home to the SmartHome service.
// Phone calls go to the Telephone (API 1.3; the 1.0 phone_call dials through it too).
//
// Threading: a context is used by the one thread running its skill, except cancel(),
// which any thread may call.
#pragma once

#include <marvin/robot.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "data/personal_data.h"
#include "devices/body.h"
#include "navigation/going_places.h"
#include "skills/eyes.h"
#include "skills/guard.h"
#include "skills/kept_answer.h"
#include "skills/sightings.h"
#include "skills/smart_home.h"
#include "skills/telephone.h"
#include "skills/user.h"

namespace marvin::skills {

// What the host lends to skills. Pointers are borrowed and must outlive every context.
struct HostServices {
  data::PersonalData* data = nullptr;
  devices::Body* body = nullptr;
  // Going places (go_to, go_stop, where_am_i): the navigator on the floor plan; null on a
  // robot without a map (those calls answer MARVIN_ERR_UNAVAILABLE).
  navigation::GoingPlaces* going_places = nullptr;
  User* user = nullptr;
  // Now, milliseconds since the Unix epoch (UTC). Default: the system clock.
  std::function<std::int64_t()> now_ms;
  std::string time_zone = "UTC";  // the owner's IANA time zone
  // The body's clock (steady, milliseconds) its scan points are stamped with; converting
  // them to Unix time reads both clocks. Default: std::chrono::steady_clock.
  std::function<std::int64_t()> steady_now_ms;
  // move() returns when the motion has run its course (true), or at once (false: the
  // MockRobot, so tests have nothing to wait for).
  bool wait_for_motion = true;
  // The id of the reminder the host announced most recently, if any (schedule_last_fired).
  // Called from skill threads: it must be thread-safe.
  std::function<std::optional<std::int64_t>()> last_fired_reminder;
  // The camera (API 1.2); null: vision_* answer MARVIN_ERR_UNAVAILABLE. Called from skill
  // threads: it must be thread-safe.
  Eyes* eyes = nullptr;
  // Smart-home devices over the home's broker (smarthome_*); null: none configured.
  // Called from skill threads: it must be thread-safe.
  SmartHome* smarthome = nullptr;
  // Finding and guarding (API 1.3). Null: sightings_find / guard / events_list answer
  // MARVIN_ERR_UNAVAILABLE. Thread-safe.
  SightingLog* sightings = nullptr;
  Guard* guard = nullptr;
  struct LoggedEvent {
    std::string kind, message;
    std::int64_t time_ms = 0;
  };
  // The owner's event log, newest first, of a kind ("" all) since a time.
  std::function<std::vector<LoggedEvent>(std::string_view kind, std::int64_t since_ms)> events;
  // The telephone (phone_*, API 1.3); null: none (MARVIN_ERR_UNAVAILABLE). Thread-safe.
  Telephone* telephone = nullptr;
};


// The system clock in milliseconds since the Unix epoch.
std::int64_t system_now_ms();

class SkillContext {
 public:
  SkillContext(std::string skill_id, std::vector<std::string> permissions, HostServices& services);
  SkillContext(const SkillContext&) = delete;
  SkillContext& operator=(const SkillContext&) = delete;

  marvin_host* host() { return reinterpret_cast<marvin_host*>(this); }
  static SkillContext& from(marvin_host* host) { return *reinterpret_cast<SkillContext*>(host); }

  const std::string& skill_id() const { return skill_id_; }
  HostServices& services() { return services_; }
  bool has_permission(const std::string& permission) const;
  // Replaces the granted permissions (the MockRobot's tests); not while a call runs.
  void set_permissions(std::vector<std::string> permissions) {
    permissions_ = std::move(permissions);
  }

  // A new request starts: clears the cancelled flag and the last error.
  void begin_request();
  // The user said "stop" or the time limit ran out: wakes a waiting move() and makes
  // is_cancelled() true until the next begin_request(). Any thread.
  void cancel();
  bool cancelled() const { return cancelled_.load(); }
  // Waits up to `ms` milliseconds or until cancel(); true if cancelled.
  bool wait_cancelled_for(std::uint32_t ms);

  // The sentence for api->last_error(); set by the table's functions.
  std::string last_error;
  // An acting call's answer kept for the skill's retry (kept_answer.h).
  KeptAnswer& kept_answer() { return kept_answer_; }

 private:
  std::string skill_id_;
  std::vector<std::string> permissions_;
  HostServices& services_;
  std::atomic<bool> cancelled_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  KeptAnswer kept_answer_;
};

// The table every native skill of this host receives. Static; valid for the process.
const marvin_robot_api* host_robot_api();

// Copies `text` into a caller's buffer following the marvin_text_out contract.
marvin_status write_text(marvin_text_out* out, std::string_view text);

// Adds the API 1.3 finding-and-guarding functions to `api` (core/skills/finding_api.cpp).
void add_finding_api(marvin_robot_api& api);
// Adds the API 1.4 guiding function (guide_to) to `api` (core/skills/guiding_api.cpp).
void add_guiding_api(marvin_robot_api& api);
// Records the known faces and objects of a vision_look answer as sightings (where the map
// puts them) and returns them as look_around's "seen" entries; `bearing_offset_deg` is the
// robot's turn since the look began. Never throws: a failing log only loses the sighting.
nlohmann::json record_sightings(SkillContext& c, const std::string& seen_json,
                                double bearing_offset_deg = 0);

}  // namespace marvin::skills
