// Inside of MockRobot, shared with SkillHarness: the host's own Robot API served from an
// in-memory store, a recording body and a scripted user.
#pragma once

#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "marvin/testing/mock_robot.hpp"
#include "skills/host_api.h"
#include "skills/in_memory_personal_data.h"

namespace marvin::testing {

struct MockRobot::Impl : devices::Body, skills::User, skills::Eyes {
  Impl(std::string skill_id, std::vector<std::string> permissions);

  // devices::Body
  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override;
  std::vector<devices::ScanPoint> latest_scan() override;
  void set_light(devices::Light light) override;

  // skills::User
  void say(std::string_view text) override;
  std::optional<std::string> ask(std::string_view question) override;

  // skills::Eyes: the scripted camera
  std::string look_json() override;
  std::string capture_photo(const std::string& skill_id) override;
  int enroll_face(const std::string& name, int frames, const std::string& who) override;
  bool forget_face(const std::string& name, const std::string& who) override;

  skills::InMemoryPersonalData data;
  nlohmann::json view;
  std::string camera_failure;
  std::vector<std::string> enrolled;
  int photos = 0;
  skills::HostServices services;
  std::unique_ptr<skills::SkillContext> context;
  std::string skill_id;
  std::int64_t now_ms = 1767603600000;  // 2026-01-05T09:00:00Z
  std::deque<std::string> answers;
  std::vector<std::string> said, asked, actions;
  std::vector<marvin_scan_point> scan;
  std::optional<std::int64_t> last_fired;
};

}  // namespace marvin::testing
