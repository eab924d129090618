// marvin::testing::MockRobot: a robot in memory for skills' unit tests.
//
// It implements the whole Robot API table (marvin/robot.h) with the host's own code, so
// permission checks, error sentences and the JSON formats are exactly the robot's, but
// with no hardware: what the skill says and does is recorded, ask() is answered from a
// queue of scripted answers, the clock and time zone are what the test sets, moves
// return at once, and schedules, contacts and storage live in memory.
//
//   marvin::testing::MockRobot robot("dice", {"storage"});
//   robot.add_answer("three");
//   marvin::Robot r(robot.api(), robot.host());   // hand these to the skill under test
//   ...
//   CHECK(robot.said() == std::vector<std::string>{"How many?", "You rolled 7."});
//
// Not thread-safe: one test thread drives it (the SkillHarness runs everything inline).
// Link MarvinSDK::testing.
#ifndef MARVIN_TESTING_MOCK_ROBOT_HPP_
#define MARVIN_TESTING_MOCK_ROBOT_HPP_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "marvin/robot.h"

namespace marvin::testing {

class SkillHarness;

class MockRobot {
 public:
  // A robot lending its table to skill `skill_id` with `permissions` (see robot.h;
  // "speech" is implicit). Clock: 2026-01-05 09:00 UTC (a Monday); time zone "UTC".
  explicit MockRobot(std::string skill_id = "test", std::vector<std::string> permissions = {});
  ~MockRobot();
  MockRobot(const MockRobot&) = delete;
  MockRobot& operator=(const MockRobot&) = delete;

  // The table and the context to hand to the skill. Valid while the MockRobot lives.
  const marvin_robot_api* api() const;
  marvin_host* host();

  // --- what the test sets up --------------------------------------------------------
  void set_permissions(std::vector<std::string> permissions);
  // Queues the user's answer to the next question; ask() with an empty queue returns
  // MARVIN_ERR_CANCELLED (as if the user had said "stop").
  void add_answer(std::string answer);
  void set_now(std::int64_t unix_ms);
  void set_time_zone(std::string iana_name);
  void set_scan(std::vector<marvin_scan_point> points);
  // As if the user said "stop": is_cancelled() becomes true, ask() and move() cancel.
  void cancel();
  // Going places (API 1.2): go_to(place) "arrives" at a place added here (case and a
  // leading "the" do not matter), which moves the robot to `room`; a blocked place makes
  // go_to give up with `reason` (MARVIN_ERR_UNAVAILABLE); any other place is not found.
  // actions() records "go_to <place>" and "stop".
  void add_place(std::string name, std::string room);
  // How far the robot would drive to a place added above: place_find() then gives it as
  // "distance_m" (without this, "distance_m" is absent, as on a robot without a path).
  void set_path_length(const std::string& place, double metres);
  void block_place(std::string name, std::string reason);
  // Guiding (API 1.4): the next guide_to to a known place tells these events, in order,
  // before it arrives (JSON as marvin_guide_event_fn gets it: {"event": "obstacle",
  // "distance_m": 1, "kind": "low", "stopped": true}); the skill's on_event may stop it.
  // "then_stop": true: the user says "stop" as that event is told (the trip ends there).
  // actions() records "guide_to <place> speed=<percent>".
  void add_guide_event(const std::string& event_json);
  // The room the robot is in: where_am_i() answers it ("": between rooms) and the smart
  // home resolves "the light" in it. Starts as "hall". With set_room_view's views, the camera
  // then sees that room's, as after go_to.
  void set_room(std::string room);
  const std::string& room() const;
  // Adds a contact the skill can find; returns its id.
  std::int64_t add_contact(const std::string& name, std::vector<std::string> aliases = {},
                           std::vector<std::string> phone_numbers = {});

  // Adds a reminder as the user could have (`at`: local "YYYY-MM-DDTHH:MM" in the robot's
  // time zone, recurrence once); returns its id.
  std::int64_t add_reminder(const std::string& title, const std::string& at);
  // As if the robot had just announced reminder `reminder_id` ("Reminder: take my pills"):
  // schedule_last_fired() serves it from now on. std::nullopt: nothing fired (the default).
  void set_last_fired(std::optional<std::int64_t> reminder_id);
  // What the camera sees from now on (API 1.2): the JSON vision_look returns (see
  // marvin/robot.h), e.g. {"faces":[{"name":"","box":[100,80,120,120]}],"objects":[]}.
  // Until this is called the mock robot has no camera (MARVIN_ERR_UNAVAILABLE).
  // vision_enroll_face names the one face in view; vision_forget_face unnames it. A face
  // named in a view (here or in set_room_view) or enrolled is a person people_list() knows.
  void set_camera_view(const std::string& seen_json);
  // The camera fails from now on ("unplugged"): vision_* answer MARVIN_ERR_UNAVAILABLE with
  // `message` as the error sentence, and nothing is enrolled or forgotten.
  void set_camera_failure(std::string message);

  // Finding and guarding (API 1.3). What the camera sees while the robot is in `room`
  // (after go_to took it there; the first view also turns the camera on, as
  // set_camera_view does), facing the way it came in: look_around sees it at its first
  // stop only; turn() records
  // "turn <degrees>"; rooms_to_search() is the robot's room, then the other rooms of
  // add_place() in the order added; place_find() knows add_place()'s names (a name
  // starting with a capital letter is a person). Sightings are kept in memory.
  void set_room_view(const std::string& room, const std::string& seen_json);
  // An event in the owner's event log (events_list), stamped now.
  void add_event(const std::string& kind, const std::string& message);
  // Guard mode as the skill left it (guard()): on or off. The mock's guard never alerts.
  bool guarding() const;

  // Smart home (smarthome_set, smarthome_devices). A device as in smarthome_devices()'s
  // "devices" ({"id", "name", "room", "type", "dimmable", ...}; "on" false and
  // "brightness" 100 when left out); it answers every command unless set_device_answers()
  // says otherwise. The broker is reachable unless set_broker_reachable(false).
  void add_device(const std::string& device_json);
  void set_device_answers(const std::string& id, bool answers);
  void set_broker_reachable(bool reachable);
  // Phone calls (API 1.3). A call to `number` (as dialled: the contact's number or sip:
  // URI) ends as `outcome`: "answer" (the default), "busy", "no_answer" or "fail"; its
  // events are queued at once (phone_wait_event never waits). actions() records
  // "phone_dial <number>", "phone_hang_up", "phone_answer", "phone_decline",
  // "phone_call_for_help".
  void set_call_outcome(const std::string& number, const std::string& outcome);
  // Someone calls: phone_state() is "incoming" from `number` until answered or declined.
  void incoming_call(const std::string& number, const std::string& name = "");
  // The other side ended the call.
  void remote_hang_up();
  // The telephone cannot call from now on (phone_dial: MARVIN_ERR_UNAVAILABLE, `reason`).
  void set_phone_failure(std::string reason);
  // false: the robot has no telephone at all (phone_*: MARVIN_ERR_UNAVAILABLE).
  void set_phone_available(bool available);
  // "idle", "ringing", "in_call", "incoming".
  std::string phone_state() const;
  // The event log, "kind: message" ("emergency: Calling Anna for help").
  std::vector<std::string> logged_events() const;
  // A contact as contacts_add takes it ({"name", "aliases", "relation", "phone_numbers",
  // "sip_uris", "emergency_order"}); returns its id. Throws naming a malformed field.
  std::int64_t add_contact_json(const std::string& contact_json);

  // The device's current state as JSON text; nullopt for an unknown id.
  std::optional<std::string> device(const std::string& id) const;

  // --- what the skill did ----------------------------------------------------------
  // Every sentence spoken, questions included, in order.
  const std::vector<std::string>& said() const;
  // The questions asked (also in said()).
  const std::vector<std::string>& asked() const;
  // Body, camera and smart-home actions in order: "light executing",
  // "move forward speed=120 ms=1500", "stop", "tilt_head 20", "capture_photo",
  // "enroll_face Anna frames=3", "forget_face Anna", "smarthome_set <id> {\"on\":true}".
  const std::vector<std::string>& actions() const;
  // Scripted answers not used yet.
  std::size_t answers_left() const;
  // Reminders the skill created, as JSON text in the README's format, soonest first.
  std::vector<std::string> reminders() const;
  // The reminder with id `id` as JSON text (with "state": "active", "done" or
  // "cancelled"), whatever its state; nullopt if there is none.
  std::optional<std::string> reminder(std::int64_t id) const;
  // The skill's stored value under `key`.
  std::optional<std::string> stored(const std::string& key) const;
  // People enrolled by face (vision_enroll_face), in order, without the forgotten ones.
  std::vector<std::string> enrolled_faces() const;
  // Forgets said(), asked() and actions().
  void clear();

 private:
  friend class SkillHarness;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::testing

#endif  // MARVIN_TESTING_MOCK_ROBOT_HPP_
