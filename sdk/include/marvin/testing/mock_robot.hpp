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
  // Adds a contact the skill can find; returns its id.
  std::int64_t add_contact(const std::string& name, std::vector<std::string> aliases = {},
                           std::vector<std::string> phone_numbers = {});

  // Adds a reminder as the user could have (`at`: local "YYYY-MM-DDTHH:MM" in the robot's
  // time zone, recurrence once); returns its id.
  std::int64_t add_reminder(const std::string& title, const std::string& at);
  // As if the robot had just announced reminder `reminder_id` ("Reminder: take my pills"):
  // schedule_last_fired() serves it from now on. std::nullopt: nothing fired (the default).
  void set_last_fired(std::optional<std::int64_t> reminder_id);

  // Smart home (smarthome_set, smarthome_devices). A device as in smarthome_devices()'s
  // "devices" ({"id", "name", "room", "type", "dimmable", ...}; "on" false and
  // "brightness" 100 when left out); it answers every command unless set_device_answers()
  // says otherwise. The broker is reachable unless set_broker_reachable(false).
  void add_device(const std::string& device_json);
  void set_device_answers(const std::string& id, bool answers);
  void set_broker_reachable(bool reachable);
  void set_room(const std::string& room);  // where the robot is ("living room" by default)
  // The device's current state as JSON text; nullopt for an unknown id.
  std::optional<std::string> device(const std::string& id) const;

  // --- what the skill did ----------------------------------------------------------
  // Every sentence spoken, questions included, in order.
  const std::vector<std::string>& said() const;
  // The questions asked (also in said()).
  const std::vector<std::string>& asked() const;
  // Body actions in order: "light executing", "move forward speed=120 ms=1500", "stop",
  // "tilt_head 20", and smart-home commands: "smarthome_set <id> {\"on\":true}".
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
  // Forgets said(), asked() and actions().
  void clear();

 private:
  friend class SkillHarness;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::testing

#endif  // MARVIN_TESTING_MOCK_ROBOT_HPP_
