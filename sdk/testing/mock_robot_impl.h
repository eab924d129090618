// Inside of MockRobot, shared with SkillHarness: the host's own Robot API served from an
// in-memory store, a recording body and a scripted user.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "marvin/testing/mock_robot.hpp"
#include "skills/host_api.h"
#include "skills/in_memory_personal_data.h"
#include "skills/scripted_eyes.h"

namespace marvin::testing {

// The scripted smart home: devices in memory that report what they are told, unless
// the test made them (or the broker) silent.
struct FakeHome : skills::SmartHome {
  nlohmann::json devices() override;
  Reply set(const std::string& device, const nlohmann::json& state) override;
  std::vector<nlohmann::json> list;
  std::vector<std::string> silent;
  bool reachable = true;
  std::string room = "hall";
  std::vector<std::string>* actions = nullptr;
};

// The scripted telephone: every call ends at once as the test said (answer by default);
// its events wait in a queue for phone_wait_event.
struct FakePhone : skills::Telephone {
  Reply dial(const std::string& number, const std::string& name) override;
  bool hang_up() override;
  bool answer() override;
  bool decline() override;
  nlohmann::json state() override;
  std::optional<nlohmann::json> wait_event(std::chrono::milliseconds timeout,
                                           const std::function<bool()>& stop) override;
  Reply call_for_help(std::vector<std::pair<std::string, std::string>> contacts) override;

  std::string outcome_of(const std::string& number) const;
  nlohmann::json event(const std::string& kind) const;

  std::map<std::string, std::string> outcomes;  // number -> answer|busy|no_answer|fail
  std::string failure;                          // non-empty: dial fails with it
  std::string call_state = "idle";
  std::string number, name;
  std::deque<nlohmann::json> events;
  std::vector<std::string>* actions = nullptr;
  skills::InMemoryPersonalData* data = nullptr;
};

struct MockRobot::Impl : devices::Body, skills::User, navigation::GoingPlaces {
  Impl(std::string skill_id, std::vector<std::string> permissions);

  // devices::Body
  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override;
  std::vector<devices::ScanPoint> latest_scan() override;
  void set_light(devices::Light light) override;

  // navigation::GoingPlaces: scripted (add_place, block_place, set_room)
  navigation::GoResult go_to(std::string_view target, const navigation::WaitFn& wait) override;
  navigation::GoResult guide_to(std::string_view target, double speed_factor,
                                const GuideFn& on_event, const navigation::WaitFn& wait) override;
  std::optional<std::string> where_am_i() override;
  bool turn(double degrees, const navigation::WaitFn& wait) override;
  std::optional<Spot> locate(double bearing_deg, double distance_m) override;
  std::vector<std::string> rooms_to_search() override;
  std::optional<PlaceInfo> find_place(std::string_view name) override;
  std::optional<double> path_length_to(std::string_view name) override;

  // skills::User
  void say(std::string_view text) override;
  std::optional<std::string> ask(std::string_view question) override;

  // A face the camera names is a person Marvin knows (people_list), as enrolment makes one
  // on the robot: named in a view, or enrolled by the skill.
  void know_person(const std::string& name);
  void know_faces_in(const std::string& seen_json);

  skills::InMemoryPersonalData data{[this] { return now_ms; }};  // the log on the mock's clock
  skills::ScriptedEyes eyes{[this](std::string action) {
    if (action.rfind("enroll_face ", 0) == 0) {
      know_person(action.substr(12, action.rfind(" frames=") - 12));
    }
    actions.push_back(std::move(action));
  }};
  skills::HostServices services;
  std::unique_ptr<skills::SkillContext> context;
  std::string skill_id;
  std::int64_t now_ms = 1767603600000;  // 2026-01-05T09:00:00Z
  std::deque<std::string> answers;
  std::vector<std::string> said, asked, actions;
  std::vector<marvin_scan_point> scan;
  std::optional<std::int64_t> last_fired;
  std::vector<std::pair<std::string, std::string>> places;   // name, room
  std::map<std::string, double> path_lengths;                // place_key -> metres
  std::vector<std::pair<std::string, std::string>> blocked;  // name, reason
  std::vector<GuideEvent> guide_events;                      // told on the next guide_to
  std::vector<bool> guide_stops;  // per guide event: the user says "stop" as it is told
  std::string room = "hall";
  FakeHome home;
  std::map<std::string, std::string> room_views;  // room -> vision_look JSON
  double heading = 0;  // degrees turned since arriving in the room
  // With set_room_view's views: the camera sees `room`'s view when facing the way it came
  // in (heading 0), else nothing. Without them the camera is left as it is.
  void show_room_view();
  skills::InMemorySightingLog sightings{[this] { return now_ms; }};
  std::unique_ptr<skills::Guard> guard;
  std::vector<skills::HostServices::LoggedEvent> events;
  FakePhone phone;
};

}  // namespace marvin::testing
