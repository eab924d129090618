// Built-in skill "guidance" (issue 22), for a person who cannot see:
//   "guide me to the kitchen" -> plans and leads the way at half the normal speed
//        (guide_to, Robot API 1.4), telling on the way, sparingly: the distance, each turn
//        about a metre before it, obstacles with their distance (named and sided when the
//        camera recognises them: "chair, one metre ahead, on your left"), a step down
//        ahead; stops for obstacles (the navigator's 0.4 m safety distance) and steps
//        down; says when there; "I can't guide you to ...: <why>" when no way is left
//   "is the way clear?"       -> from the sonar sweep straight ahead
//   "what's in front of me?"  -> the sonar's nearest obstacle, told wall from low thing from
//        step down, and what the camera recognises, with direction and distance
// The sonar sweeps in the vertical plane of the heading, up and (the simulated robot's)
// down: a reading at tilt θ and slant distance D hit something D_x = D cos θ ahead at D_y =
// D sin θ (= D_x tan θ) above the sonar. Echoes at the same D_x from high up are a wall (or
// something tall); echoes only from low down are a low obstacle; a downward echo clearly
// longer than the floor's (h / sin|θ|) is a step down. The same rules as the navigator's
// (core/navigation/sonar_sweep.h; a skill sees only the SDK, so they are repeated here).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <marvin/skill.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/spoken_text.h"

namespace {

using marvin::builtin::capital;

using nlohmann::json;

constexpr double kGuidePi = 3.14159265358979323846;
constexpr double kRangeM = 2.5;         // the sonar's "no echo"
constexpr double kClearM = 1.5;         // "the way is clear" means nothing closer than this
constexpr double kTallM = 0.35;         // higher than this above the sonar: tall (a wall)
constexpr double kSameM = 0.15;         // echoes this close in D_x are the same thing
constexpr double kSonarHeightM = 0.25;  // the robot's sonar above the floor
constexpr std::uint32_t kGuideSpeedPercent = 50;  // a slow walk: 0.12 m/s in the sim

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
  enum Kind { kClear, kWall, kLow, kStepDown } kind = kClear;
  double x = kRangeM;  // horizontal distance to it
};

const char* words(Ahead::Kind kind) {
  switch (kind) {
    case Ahead::kWall:
      return "a wall or something tall";
    case Ahead::kLow:
      return "something low, below your knees";
    case Ahead::kStepDown:
      return "a step down";
    case Ahead::kClear:
      break;
  }
  return "nothing";
}

Ahead nearest_ahead(const std::vector<marvin_scan_point>& scan) {
  Ahead a;
  double nearest = kRangeM, drop = kRangeM;
  std::vector<std::pair<double, double>> things;  // D_x, D_y
  for (const auto& p : scan) {
    if (p.angle_deg < -90 || p.angle_deg > 60 || p.distance_m >= kRangeM) continue;
    const double t = p.angle_deg * kGuidePi / 180;
    const double dx = p.distance_m * std::cos(t), dy = p.distance_m * std::sin(t);
    if (p.angle_deg < -1) {
      const double floor_m = kSonarHeightM / std::sin(-t);
      if (p.distance_m > floor_m * 1.15 + 0.03) {
        drop = std::min(drop, floor_m * std::cos(t));
        continue;
      }
      if (p.distance_m >= floor_m * 0.85 - 0.03) continue;  // the floor
    }
    things.emplace_back(dx, dy);
    nearest = std::min(nearest, dx);
  }
  if (drop < kRangeM && drop <= nearest) {
    a.kind = Ahead::kStepDown;
    a.x = drop;
    return a;
  }
  if (nearest >= kRangeM) return a;
  a.x = nearest;
  a.kind = Ahead::kLow;
  for (const auto& [dx, dy] : things) {
    if (std::fabs(dx - nearest) < kSameM && dy > kTallM) a.kind = Ahead::kWall;
  }
  return a;
}

// "on your left" / "on your right" / "straight ahead" for a box in a frame `width` wide.
std::string side_of(const json& box, double width) {
  if (!box.is_array() || box.size() != 4) return "straight ahead";
  const double cx = box[0].get<double>() + box[2].get<double>() / 2;
  if (cx < width / 3) return "on your left";
  if (cx > 2 * width / 3) return "on your right";
  return "straight ahead";
}

class GuidanceSkill : public marvin::Skill {
 public:
  using Skill::Skill;

  void handle(const marvin::Request& r) override {
    if (r.intent == "guide")
      guide(lower(r.slots.value("place", std::string())));
    else if (r.intent == "way_clear")
      way_clear(r.utterance);
    else if (r.intent == "in_front")
      in_front();
    else
      throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + r.intent + "'");
  }

 private:
  void guide(std::string place) {
    // "my bedroom" is the map's "bedroom"; "my chair", not on the map, is said as "your chair".
    const bool mine = place.rfind("my ", 0) == 0;
    std::string shown = mine ? "your " + place.substr(3) : "the " + place;
    try {
      std::optional<json> info = robot().place_find(place);
      if (!info && mine) {
        info = robot().place_find(place.substr(3));
        if (info) {
          place.erase(0, 3);
          shown = "the " + place;
        }
      }
      if (!info) {
        robot().say("I don't know where " + shown + " is.");
        return;
      }
      if (info->value("kind", "") == "person") shown = info->value("name", place);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
    }
    robot().say("Follow me to " + shown + ". I'll go slowly and tell you what's ahead.");
    try {
      robot().guide_to(place, kGuideSpeedPercent, [this](const json& e) {
        tell(e);
        return true;
      });
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

  // One thing on the way, in a short sentence.
  void tell(const json& e) {
    const std::string event = e.value("event", "");
    const double d = e.value("distance_m", 0.0);
    if (event == "start") {
      const double left = e.value("distance_left_m", 0.0);
      if (left >= 1) robot().say("It's about " + metres(left) + ".");
    } else if (event == "turn") {
      robot().say("In " + metres(d) + ", we turn " + e.value("turn", "") + ".");
    } else if (event == "step_down") {
      robot().say("Careful: step down ahead, " + metres(d) + ". I've stopped.");
    } else if (event == "obstacle") {
      std::string what = named_ahead();
      if (what.empty()) {
        what = e.value("kind", "") == "wall" ? words(Ahead::kWall) : "something low";
        what += ", " + metres(d) + " ahead";
      } else {
        // "chair, one metre ahead, on your left"
        const auto comma = what.find(',');
        what = what.substr(0, comma) + ", " + metres(d) + " ahead" +
               (what.find("straight ahead") == std::string::npos ? what.substr(comma) : "");
      }
      robot().say(capital(what) + (e.value("stopped", false) ? ". I'm stopping." : "."));
    }
  }

  // What the camera recognises ahead, "chair, on your left" (the biggest thing), or "".
  std::string named_ahead() {
    try {
      const json seen = robot().vision_look();
      const double width = seen.value("width", 640.0);
      const json objects = seen.value("objects", json::array());
      const json* best = nullptr;
      double best_area = 0;
      for (const json& o : objects) {
        const json box = o.value("box", json::array({0, 0, 0, 0}));
        if (!box.is_array() || box.size() != 4) continue;
        const double area = box[2].get<double>() * box[3].get<double>();
        if (area > best_area) {
          best_area = area;
          best = &o;
        }
      }
      if (!best) return "";
      return best->value("label", "something") + ", " + side_of(best->value("box", json()), width);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      return "";  // no camera: the sonar still tells
    }
  }

  // "Is the way clear?" and "is anything in my way?" ask the same with opposite answers.
  void way_clear(const std::string& utterance) {
    bool asks_for_obstacle = false;
    for (const std::string& w : marvin::builtin::words_in(utterance)) {
      for (const char* o : {"anything", "something", "obstacle", "obstacles", "blocked",
                            "blocking", "block"}) {
        asks_for_obstacle = asks_for_obstacle || w == o;
      }
    }
    const Ahead a = nearest_ahead(robot().obstacle_scan());
    if (a.kind == Ahead::kClear || (a.x >= kClearM && a.kind != Ahead::kStepDown)) {
      robot().say(asks_for_obstacle
                      ? "No, nothing is in the way for at least " + metres(a.x) + "."
                      : "Yes, the way ahead is clear for at least " + metres(a.x) + ".");
      return;
    }
    robot().say((asks_for_obstacle ? "Yes: " : "No: ") +
                std::string(a.kind == Ahead::kLow ? "something low" : words(a.kind)) + ", " +
                metres(a.x) + " ahead.");
  }

  void in_front() {
    std::vector<std::string> parts;
    const Ahead a = nearest_ahead(robot().obstacle_scan());
    if (a.kind != Ahead::kClear)
      parts.push_back(std::string(words(a.kind)) + ", " + metres(a.x) + " ahead");
    try {
      const json seen = robot().vision_look();
      const double width = seen.value("width", 640.0);
      auto side = [&](const json& box) { return side_of(box, width); };
      for (const json& o : seen.value("objects", json::array())) {
        parts.push_back("a " + o.value("label", "thing") + ", " +
                        side(o.value("box", json::array({0, 0, 0, 0}))));
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
