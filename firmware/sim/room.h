// The simulated room and body of marvin-mcu-sim: walls and box obstacles from JSON, a
// differential-drive base, and the HC-SR04's echo by ray casting.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace marvin::mcusim {

struct Segment {
  double x1, y1, x2, y2, height_m;
};

struct RobotPose {
  double x = 0, y = 0, heading_deg = 0;
};

struct Room {
  double ceiling_m = 2.5;
  double radius_m = 0.15, track_m = 0.25, max_speed_m_s = 0.4, sonar_height_m = 0.25;
  RobotPose start;
  std::vector<Segment> segments;  // walls, and the four sides of each obstacle box
};

// Parses a room (see firmware/sim/rooms/corridor.json). Throws std::runtime_error naming
// the file and the field that is wrong.
Room load_room(const std::string& path);

// The slant distance the sonar measures at sweep angle `angle_deg` (0 = ahead, 90 = up,
// 120 = up and backwards, in the vertical plane of the heading), or a value >= 2.5 if
// nothing is within range. Obstacles lower than the ray where it crosses them are missed.
double sonar_distance_m(const Room& room, const RobotPose& pose, double angle_deg);

// The echo width in us the HC-SR04 gives for that distance (0 when out of range).
std::uint32_t echo_us_for(double distance_m);

// Moves the body for dt seconds with wheel speeds in m/s (differential drive). Returns
// false, leaving the pose unchanged, if the move would put the body into a wall or obstacle.
bool step_body(const Room& room, RobotPose& pose, double left_m_s, double right_m_s, double dt_s);

// Distance from the robot's centre to the nearest segment, in metres.
double clearance_m(const Room& room, const RobotPose& pose);

}  // namespace marvin::mcusim
