#include "skills/scripted_eyes.h"

#include <algorithm>
#include <stdexcept>

namespace marvin::skills {

void ScriptedEyes::set_view(const std::string& seen_json) {
  nlohmann::json view;
  try {
    view = nlohmann::json::parse(seen_json);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument("camera view: not JSON at byte " + std::to_string(e.byte));
  }
  if (!view.is_object()) throw std::invalid_argument("camera view: expected a JSON object");
  if (!view.contains("faces")) view["faces"] = nlohmann::json::array();
  if (!view.contains("objects")) view["objects"] = nlohmann::json::array();
  view_ = std::move(view);
}

void ScriptedEyes::check_working() const {
  if (!failure_.empty()) throw EyesUnavailable(failure_);
}

std::string ScriptedEyes::look_json() {
  check_working();
  return view_.dump();
}

std::string ScriptedEyes::capture_photo(const std::string& skill_id) {
  check_working();
  action_("capture_photo");
  return "/mock/" + skill_id + "/photo-" + std::to_string(++photos_) + ".jpg";
}

int ScriptedEyes::enroll_face(const std::string& name, int frames, const std::string&) {
  check_working();
  const int count = static_cast<int>(view_["faces"].size());
  if (count != 1) {
    throw NoSingleFace(count == 0 ? "no face in view"
                                  : std::to_string(count) + " faces in view; one at a time please",
                       count);
  }
  view_["faces"][0]["name"] = name;
  enrolled_.erase(std::remove(enrolled_.begin(), enrolled_.end(), name), enrolled_.end());
  enrolled_.push_back(name);
  action_("enroll_face " + name + " frames=" + std::to_string(frames));
  return frames;
}

bool ScriptedEyes::forget_face(const std::string& name, const std::string&) {
  check_working();
  auto it = std::find(enrolled_.begin(), enrolled_.end(), name);
  if (it == enrolled_.end()) return false;
  enrolled_.erase(it);
  for (auto& f : view_["faces"]) {
    if (f.value("name", "") == name) f["name"] = "";
  }
  action_("forget_face " + name);
  return true;
}

void ScriptedEyes::teach_object(const std::string& name) {
  check_working();
  if (std::find(taught_.begin(), taught_.end(), name) == taught_.end()) taught_.push_back(name);
  action_("teach_object " + name);
}

std::string ScriptedEyes::find_object_json(const std::string& name) {
  check_working();
  nlohmann::json out = {{"name", name}, {"found", false}};
  bool known = std::find(taught_.begin(), taught_.end(), name) != taught_.end();
  for (const auto& o : view_["objects"]) {
    if (o.value("label", "") == name) {
      known = true;
      out["found"] = true;
      out["box"] = o.value("box", nlohmann::json::array());
      break;
    }
  }
  return known ? out.dump() : "";
}

}  // namespace marvin::skills
