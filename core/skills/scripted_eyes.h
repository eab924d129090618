// ScriptedEyes: a camera whose view a test sets (the MockRobot's and `marvin skill test`'s
// robot). vision_look returns the view; enrolment names the one unnamed face in view and
// forgetting unnames it; a set failure makes every call unavailable, changing nothing.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "skills/eyes.h"

namespace marvin::skills {

class ScriptedEyes final : public Eyes {
 public:
  // `action` hears "capture_photo", "enroll_face Anna frames=3", "forget_face Anna".
  explicit ScriptedEyes(std::function<void(std::string)> action) : action_(std::move(action)) {}

  // The JSON of vision_look (marvin/robot.h); "faces" and "objects" default to empty.
  // Throws std::invalid_argument naming the byte when it is not JSON.
  void set_view(const std::string& seen_json);
  void set_failure(std::string message) { failure_ = std::move(message); }
  const std::vector<std::string>& enrolled() const { return enrolled_; }

  std::string look_json() override;
  std::string capture_photo(const std::string& skill_id) override;
  int enroll_face(const std::string& name, int frames, const std::string& who) override;
  bool forget_face(const std::string& name, const std::string& who) override;
  // Teaching records the name; finding looks for an object of that label in the view.
  void teach_object(const std::string& name) override;
  std::string find_object_json(const std::string& name) override;

 private:
  void check_working() const;

  std::function<void(std::string)> action_;
  nlohmann::json view_ = {{"faces", nlohmann::json::array()}, {"objects", nlohmann::json::array()}};
  std::string failure_;
  std::vector<std::string> enrolled_;
  std::vector<std::string> taught_;
  int photos_ = 0;
};

}  // namespace marvin::skills
