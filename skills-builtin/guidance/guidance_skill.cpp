// Built-in skill "guidance" (issue 22), for a person who cannot see:
//   "guide me to the kitchen" -> plans, leads the way (the navigator stops for anything the
//        sonar finds closer than its safety distance, 0.4 m, and plans around it), says
//        when there; "I can't guide you to ...: <why>" when no path is left
//   "is the way clear?"       -> from the sonar sweep straight ahead
//   "what's in front of me?"  -> the sonar's nearest obstacle, told wall from low thing, and
//        what the camera recognises, with direction and distance
// The sonar sweeps in the vertical plane of the heading (0 = level, up to 60 degrees): a
// reading at tilt θ and slant distance D hit something D_x = D cos θ ahead at D_y =
// D_x tan θ (= D sin θ) above the sonar. Echoes at the same D_x from low and high tilts are a
// wall (or something tall); echoes only from low tilts are a low obstacle (a step up, a box,
// a chair's seat). The sonar cannot look down, so a step down is not found (limit).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <marvin/skill.hpp>

namespace {

using nlohmann::json;

constexpr double kGuidePi = 3.14159265358979323846;
constexpr double kRangeM = 2.5;      // the sonar's "no echo"
constexpr double kClearM = 1.5;      // "the way is clear" means nothing closer than this
constexpr double kTallM = 0.35;      // higher than this above the sonar: tall (a wall)
constexpr double kSameM = 0.15;      // echoes this close in D_x are the same thing

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  while (!s.empty() && (s.back() == '?' || s.back() == '.' || s.back() == ' ')) s.pop_back();
  if (s.rfind("the ", 0) == 0) s.erase(0, 4);
  return s;
}

// "one metre", "1.5 metres", "40 centimetres".
std::string metres(double m) {
  if (m < 0.95) return std::to_string(static_cast<int>(std::lround(m * 10)) * 10) + " centimetres";
  const double r = std::round(m * 2) / 2;
  if (std::fabs(r - 1) < 1e-9) return "one metre";
  char buf[32];
  std::snprintf(buf, sizeof buf, r == std::floor(r) ? "%.0f metres" : "%.1f metres", r);
  return buf;
}

struct Ahead {
  bool found = false;
  double x = kRangeM;    // horizontal distance to the nearest thing ahead
  bool tall = false;     // echoes from it above kTallM: a wall or something tall
};

Ahead nearest_ahead(const std::vector<marvin_scan_point>& scan) {
  Ahead a;
  for (const auto& p : scan) {
    if (p.angle_deg < 0 || p.angle_deg > 60 || p.distance_m >= kRangeM) continue;
    const double t = p.angle_deg * kGuidePi / 180;
    const double dx = p.distance_m * std::cos(t);
    if (dx < a.x) {
      a.x = dx;
      a.found = true;
    }
  }
  if (!a.found) return a;
  for (const auto& p : scan) {
    if (p.angle_deg < 0 || p.angle_deg > 60 || p.distance_m >= kRangeM) continue;
    const double t = p.angle_deg * kGuidePi / 180;
    const double dx = p.distance_m * std::cos(t);
    const double dy = dx * std::tan(t);
    if (std::fabs(dx - a.x) < kSameM && dy > kTallM) a.tall = true;
  }
  return a;
}

class GuidanceSkill : public marvin::Skill {
 public:
  using Skill::Skill;

  void handle(const marvin::Request& r) override {
    if (r.intent == "guide") guide(lower(r.slots.value("place", std::string())));
    else if (r.intent == "way_clear") way_clear();
    else if (r.intent == "in_front") in_front();
    else throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + r.intent + "'");
  }

 private:
  void guide(const std::string& place) {
    std::string shown = "the " + place;
    try {
      if (auto info = robot().place_find(place)) {
        if (info->value("kind", "") == "person") shown = info->value("name", place);
      } else {
        robot().say("I don't know where " + shown + " is.");
        return;
      }
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
    }
    robot().say("Follow me to " + shown + ". I'll stop if something is in the way.");
    try {
      robot().go_to(place);
    } catch (const marvin::Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) {
        robot().say("I don't know where " + shown + " is.");
        return;
      }
      if (e.status() == MARVIN_ERR_UNAVAILABLE) {
        robot().say("I can't guide you to " + shown + ": " + e.what() + ".");
        return;
      }
      throw;  // "stop": the wheels are stopped; the manager answers
    }
    robot().say("We're there: " + shown + ".");
  }

  void way_clear() {
    const Ahead a = nearest_ahead(robot().obstacle_scan());
    if (!a.found || a.x >= kClearM) {
      robot().say("Yes, the way ahead is clear for at least " + metres(a.found ? a.x : kRangeM) + ".");
      return;
    }
    robot().say("No: " + std::string(a.tall ? "a wall or something tall" : "something low") +
                ", " + metres(a.x) + " ahead.");
  }

  void in_front() {
    std::vector<std::string> parts;
    const Ahead a = nearest_ahead(robot().obstacle_scan());
    if (a.found) {
      parts.push_back(std::string(a.tall ? "a wall or something tall" : "something low, below your knees") +
                      ", " + metres(a.x) + " ahead");
    }
    try {
      const json seen = robot().vision_look();
      const double width = seen.value("width", 640.0);
      auto side = [&](const json& box) {
        const double cx = box[0].get<double>() + box[2].get<double>() / 2;
        if (cx < width / 3) return std::string("on your left");
        if (cx > 2 * width / 3) return std::string("on your right");
        return std::string("straight ahead");
      };
      for (const json& o : seen.value("objects", json::array())) {
        parts.push_back("a " + o.value("label", "thing") + ", " + side(o.value("box", json::array({0, 0, 0, 0}))));
      }
      for (const json& f : seen.value("faces", json::array())) {
        const std::string who = f.value("name", "");
        parts.push_back((who.empty() ? std::string("someone I don't know") : who) + ", " +
                        side(f.value("box", json::array({0, 0, 0, 0}))));
      }
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;  // no camera: the sonar still tells
    }
    if (parts.empty()) {
      robot().say("Nothing within " + metres(kRangeM) + " ahead.");
      return;
    }
    std::string sentence;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      sentence += (i == 0 ? "" : i + 1 == parts.size() ? " and " : "; ") + parts[i];
    }
    sentence[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(sentence[0])));
    robot().say(sentence + ".");
  }
};

}  // namespace

MARVIN_SKILL(GuidanceSkill, "guidance")
