// The simulated room. See room.h.
#include "room.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace marvin::mcusim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxRangeM = 2.5;
constexpr double kSoundM_S = 346.0;

double rad(double deg) { return deg * kPi / 180.0; }

// Distance along the ray (ox, oy) + t (dx, dy), t >= 0, to the segment; infinity if none.
double ray_hit(double ox, double oy, double dx, double dy, const Segment& s) {
  double ex = s.x2 - s.x1, ey = s.y2 - s.y1;
  double denom = dx * ey - dy * ex;
  if (std::fabs(denom) < 1e-12) return std::numeric_limits<double>::infinity();
  double wx = s.x1 - ox, wy = s.y1 - oy;
  double t = (wx * ey - wy * ex) / denom;
  double u = (wx * dy - wy * dx) / denom;
  if (t < 0 || u < 0 || u > 1) return std::numeric_limits<double>::infinity();
  return t;
}

double point_segment(double px, double py, const Segment& s) {
  double ex = s.x2 - s.x1, ey = s.y2 - s.y1;
  double len2 = ex * ex + ey * ey;
  double u = len2 > 0 ? ((px - s.x1) * ex + (py - s.y1) * ey) / len2 : 0;
  u = std::fmax(0, std::fmin(1, u));
  return std::hypot(px - (s.x1 + u * ex), py - (s.y1 + u * ey));
}

double number(const nlohmann::json& j, const char* key, double fallback, const std::string& where) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) throw std::runtime_error(where + ": '" + key + "' must be a number");
  return j[key].get<double>();
}

std::pair<double, double> point(const nlohmann::json& j, const char* key,
                                const std::string& where) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 2 || !j[key][0].is_number() ||
      !j[key][1].is_number())
    throw std::runtime_error(where + ": '" + key + "' must be [x, y] in metres");
  return {j[key][0].get<double>(), j[key][1].get<double>()};
}

}  // namespace

Room load_room(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the room file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(path + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error(path + ": the room must be a JSON object");
  Room room;
  room.ceiling_m = number(j, "ceiling_m", room.ceiling_m, path);
  if (j.contains("robot")) {
    const auto& r = j["robot"];
    std::string where = path + ": robot";
    room.start.x = number(r, "x", 0, where);
    room.start.y = number(r, "y", 0, where);
    room.start.heading_deg = number(r, "heading_deg", 0, where);
    room.radius_m = number(r, "radius_m", room.radius_m, where);
    room.track_m = number(r, "track_m", room.track_m, where);
    room.max_speed_m_s = number(r, "max_speed_m_s", room.max_speed_m_s, where);
    room.sonar_height_m = number(r, "sonar_height_m", room.sonar_height_m, where);
  }
  if (j.contains("walls")) {
    if (!j["walls"].is_array()) throw std::runtime_error(path + ": 'walls' must be an array");
    for (std::size_t i = 0; i < j["walls"].size(); ++i) {
      std::string where = path + ": walls[" + std::to_string(i) + "]";
      const auto& w = j["walls"][i];
      auto [x1, y1] = point(w, "from", where);
      auto [x2, y2] = point(w, "to", where);
      room.segments.push_back({x1, y1, x2, y2, number(w, "height_m", room.ceiling_m, where)});
    }
  }
  if (j.contains("obstacles")) {
    if (!j["obstacles"].is_array())
      throw std::runtime_error(path + ": 'obstacles' must be an array");
    for (std::size_t i = 0; i < j["obstacles"].size(); ++i) {
      std::string where = path + ": obstacles[" + std::to_string(i) + "]";
      const auto& o = j["obstacles"][i];
      auto [x1, y1] = point(o, "min", where);
      auto [x2, y2] = point(o, "max", where);
      double h = number(o, "height_m", 0.5, where);
      room.segments.push_back({x1, y1, x2, y1, h});
      room.segments.push_back({x2, y1, x2, y2, h});
      room.segments.push_back({x2, y2, x1, y2, h});
      room.segments.push_back({x1, y2, x1, y1, h});
    }
  }
  return room;
}

double sonar_distance_m(const Room& room, const RobotPose& pose, double angle_deg) {
  // Fold the sweep angle into "elevation above the horizontal" along the heading or
  // against it (past 90 degrees the ray points backwards).
  double heading = pose.heading_deg;
  double elevation = angle_deg;
  if (angle_deg > 90) {
    heading += 180;
    elevation = 180 - angle_deg;
  }
  double best = std::numeric_limits<double>::infinity();
  double up = room.ceiling_m - room.sonar_height_m;
  if (elevation > 0.01) best = up / std::sin(rad(elevation));
  if (elevation < 89.99) {
    double dx = std::cos(rad(heading)), dy = std::sin(rad(heading));
    double tan_e = std::tan(rad(elevation)), cos_e = std::cos(rad(elevation));
    for (const Segment& s : room.segments) {
      double r = ray_hit(pose.x, pose.y, dx, dy, s);
      if (!std::isfinite(r)) continue;
      if (room.sonar_height_m + r * tan_e > s.height_m) continue;  // passes over it
      best = std::fmin(best, r / cos_e);
    }
  }
  return best;
}

std::uint32_t echo_us_for(double distance_m) {
  if (!(distance_m < kMaxRangeM)) return 0;
  return static_cast<std::uint32_t>(std::lround(2.0 * distance_m / kSoundM_S * 1e6));
}

double clearance_m(const Room& room, const RobotPose& pose) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : room.segments) best = std::fmin(best, point_segment(pose.x, pose.y, s));
  return best;
}

bool step_body(const Room& room, RobotPose& pose, double left_m_s, double right_m_s, double dt_s) {
  double v = (left_m_s + right_m_s) / 2, w = (right_m_s - left_m_s) / room.track_m;
  RobotPose next = pose;
  next.heading_deg += w * dt_s * 180.0 / kPi;
  double h = rad((pose.heading_deg + next.heading_deg) / 2);
  next.x += v * dt_s * std::cos(h);
  next.y += v * dt_s * std::sin(h);
  if (clearance_m(room, next) < room.radius_m && clearance_m(room, next) < clearance_m(room, pose))
    return false;
  pose = next;
  return true;
}

}  // namespace marvin::mcusim
