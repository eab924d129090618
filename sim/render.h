// Pictures of the simulated home: the floor plan with rooms, walls, doors, furniture,
// places, objects and people; the robot, the path it follows, its sonar rays and its
// camera's field of view. `marvin world render` and `marvin run --sim --show` use them.
#pragma once

#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "navigation/geometry.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace marvin::sim {

struct MapView {
  double pixels_per_m = 60;
  bool labels = true;
};

// What to draw on top of the plan.
struct RobotView {
  bool shown = false;
  navigation::Pose pose;
  double radius_m = 0.15;
  double head_deg = 0;
  std::vector<navigation::Vec2> path;
  std::vector<SonarSample> sonar;  // drawn along the heading (horizontal part)
  double camera_fov_deg = 60;
  double camera_range_m = 3;
};

// The picture, BGR.
cv::Mat render_map(const World& world, const RobotView& robot, const MapView& view = {});
// The robot as the simulator has it now (true pose, latest sonar).
RobotView robot_view(const Simulator& sim, std::vector<navigation::Vec2> path = {});
// Writes a PNG atomically (a temporary file renamed over `file`), so a viewer never sees a
// half-written picture. Throws std::runtime_error naming the file.
void write_png(const cv::Mat& image, const std::filesystem::path& file);

}  // namespace marvin::sim
