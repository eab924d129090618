#include "sim/render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace marvin::sim {
namespace {

using navigation::Vec2;

cv::Scalar colour(const std::string& hex) {
  unsigned r = 200, g = 200, b = 200;
  if (hex.size() == 7 && hex[0] == '#') std::sscanf(hex.c_str() + 1, "%02x%02x%02x", &r, &g, &b);
  return cv::Scalar(b, g, r);
}

struct Canvas {
  navigation::Box bounds;
  double scale;
  int margin = 30;
  cv::Point px(Vec2 p) const {
    // y grows north in the world, down in the picture.
    return {margin + static_cast<int>(std::lround((p.x - bounds.min.x) * scale)),
            margin + static_cast<int>(std::lround((bounds.max.y - p.y) * scale))};
  }
};

void label(cv::Mat& img, const std::string& text, cv::Point at, cv::Scalar c, double size = 0.4) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, size, c, 1, cv::LINE_AA);
}

}  // namespace

RobotView robot_view(const Simulator& sim, std::vector<navigation::Vec2> path) {
  RobotView v;
  v.shown = true;
  v.pose = sim.pose();
  v.radius_m = sim.world().robot.radius_m;
  v.head_deg = sim.head_deg();
  v.path = std::move(path);
  for (const auto& [angle, s] : sim.latest_sonar()) v.sonar.push_back(s);
  return v;
}

cv::Mat render_map(const World& world, const RobotView& robot, const MapView& view) {
  Canvas c{world.map.bounds(), view.pixels_per_m};
  const int w = static_cast<int>((c.bounds.max.x - c.bounds.min.x) * c.scale) + 2 * c.margin;
  const int h = static_cast<int>((c.bounds.max.y - c.bounds.min.y) * c.scale) + 2 * c.margin;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(250, 250, 250));
  // Rooms: floors and names.
  for (std::size_t i = 0; i < world.map.rooms.size(); ++i) {
    const auto& room = world.map.rooms[i];
    std::vector<cv::Point> poly;
    for (Vec2 p : room.outline) poly.push_back(c.px(p));
    cv::fillPoly(img, std::vector<std::vector<cv::Point>>{poly}, colour(world.room_colours[i]));
  }
  // Furniture and clutter.
  for (const auto& f : world.map.furniture) {
    cv::rectangle(img, c.px(f.box.min), c.px(f.box.max), cv::Scalar(120, 130, 140), cv::FILLED);
    cv::rectangle(img, c.px(f.box.min), c.px(f.box.max), cv::Scalar(60, 60, 60), 1);
    if (view.labels)
      label(img, f.name, c.px({f.box.min.x + 0.03, (f.box.min.y + f.box.max.y) / 2}),
            cv::Scalar(255, 255, 255), 0.33);
  }
  for (const auto& f : world.clutter) {
    cv::rectangle(img, c.px(f.box.min), c.px(f.box.max), cv::Scalar(40, 90, 200), cv::FILLED);
    if (view.labels)
      label(img, f.name, c.px({f.box.min.x, f.box.max.y + 0.05}), cv::Scalar(40, 90, 200), 0.35);
  }
  // Walls; closed doors in brown over them.
  for (const auto& s : world.map.walls)
    cv::line(img, c.px(s.a), c.px(s.b), cv::Scalar(30, 30, 30), 4);
  for (const auto& d : world.map.doors) {
    if (!d.open) cv::line(img, c.px(d.a), c.px(d.b), cv::Scalar(40, 80, 140), 4);
  }
  if (view.labels) {
    for (const auto& room : world.map.rooms) {
      cv::Point at = c.px(room.spot);
      label(img, room.name, {at.x - 30, at.y - 12}, cv::Scalar(90, 40, 40), 0.5);
    }
  }
  // Places, objects, people.
  for (const auto& p : world.map.places) {
    cv::drawMarker(img, c.px(p.at), cv::Scalar(0, 140, 0), cv::MARKER_CROSS, 8, 2);
    if (view.labels) label(img, p.name, c.px(p.at) + cv::Point(5, 12), cv::Scalar(0, 110, 0), 0.33);
  }
  for (const auto& o : world.objects) {
    cv::circle(img, c.px(o.at), 5, cv::Scalar(0, 140, 255), cv::FILLED);
    if (view.labels)
      label(img, o.name, c.px(o.at) + cv::Point(6, -4), cv::Scalar(0, 100, 200), 0.35);
  }
  for (const auto& p : world.people) {
    cv::circle(img, c.px(p.at), 8, cv::Scalar(200, 80, 0), cv::FILLED);
    if (view.labels) label(img, p.name, c.px(p.at) + cv::Point(9, 4), cv::Scalar(160, 60, 0), 0.45);
  }
  if (!robot.shown) return img;
  const navigation::Pose& pose = robot.pose;
  // The camera's field of view: a translucent wedge, cut by the walls.
  {
    cv::Mat overlay = img.clone();
    std::vector<cv::Point> wedge{c.px(pose.position())};
    const double half = robot.camera_fov_deg * navigation::kPi / 360;
    for (int k = 0; k <= 48; ++k) {
      const double a = pose.heading - half + 2 * half * k / 48.0;
      const Vec2 dir{std::cos(a), std::sin(a)};
      double reach = robot.camera_range_m;
      for (const auto& s : world.map.walls)
        reach = std::min(reach, navigation::ray_segment(pose.position(), dir, s.a, s.b));
      wedge.push_back(c.px(pose.position() + dir * reach));
    }
    cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{wedge}, cv::Scalar(0, 220, 255));
    cv::addWeighted(overlay, 0.25, img, 0.75, 0, img);
  }
  // The path.
  for (std::size_t i = 1; i < robot.path.size(); ++i)
    cv::line(img, c.px(robot.path[i - 1]), c.px(robot.path[i]), cv::Scalar(220, 0, 180), 2,
             cv::LINE_AA);
  for (Vec2 p : robot.path) cv::circle(img, c.px(p), 3, cv::Scalar(220, 0, 180), cv::FILLED);
  // Sonar rays: the horizontal part of each reading along the heading (red: an echo).
  for (const SonarSample& s : robot.sonar) {
    double heading = pose.heading, elevation = s.angle_deg;
    if (elevation > 90) {
      heading += navigation::kPi;
      elevation = 180 - elevation;
    }
    const double horizontal = s.distance_m * std::cos(elevation * navigation::kPi / 180);
    const Vec2 end{pose.x + std::cos(heading) * horizontal,
                   pose.y + std::sin(heading) * horizontal};
    cv::line(img, c.px(pose.position()), c.px(end),
             s.echo ? cv::Scalar(0, 0, 230) : cv::Scalar(170, 170, 170), 1, cv::LINE_AA);
    if (s.echo) cv::circle(img, c.px(end), 3, cv::Scalar(0, 0, 230), cv::FILLED);
  }
  // The robot.
  const int r = std::max(3, static_cast<int>(robot.radius_m * c.scale));
  cv::circle(img, c.px(pose.position()), r, cv::Scalar(40, 160, 40), cv::FILLED, cv::LINE_AA);
  cv::circle(img, c.px(pose.position()), r, cv::Scalar(0, 60, 0), 2, cv::LINE_AA);
  cv::line(img, c.px(pose.position()),
           c.px({pose.x + std::cos(pose.heading) * robot.radius_m * 1.6,
                 pose.y + std::sin(pose.heading) * robot.radius_m * 1.6}),
           cv::Scalar(0, 60, 0), 2, cv::LINE_AA);
  return img;
}

void write_png(const cv::Mat& image, const std::filesystem::path& file) {
  const std::filesystem::path tmp = file.string() + ".tmp.png";
  if (!cv::imwrite(tmp.string(), image))
    throw std::runtime_error(file.string() + ": cannot write the picture");
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot write the picture: " + ec.message());
}

}  // namespace marvin::sim
