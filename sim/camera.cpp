#include "sim/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace marvin::sim {
namespace {

using navigation::Vec2;

cv::Vec3b floor_colour(const World& world, Vec2 at) {
  for (std::size_t i = 0; i < world.map.rooms.size(); ++i) {
    if (navigation::polygon_contains(world.map.rooms[i].outline, at)) {
      unsigned r = 200, g = 200, b = 200;
      std::sscanf(world.room_colours[i].c_str(), "#%02x%02x%02x", &r, &g, &b);
      return cv::Vec3b(static_cast<uchar>(b), static_cast<uchar>(g), static_cast<uchar>(r));
    }
  }
  return cv::Vec3b(160, 160, 160);
}

cv::Vec3b shade(cv::Vec3b c, double k) {
  return cv::Vec3b(static_cast<uchar>(std::clamp(c[0] * k, 0.0, 255.0)),
                   static_cast<uchar>(std::clamp(c[1] * k, 0.0, 255.0)),
                   static_cast<uchar>(std::clamp(c[2] * k, 0.0, 255.0)));
}

// Fills rows [top, bottom) of column x.
void fill_column(cv::Mat& img, int x, double top, double bottom, cv::Vec3b c) {
  const int y0 = std::max(0, static_cast<int>(std::floor(top)));
  const int y1 = std::min(img.rows, static_cast<int>(std::ceil(bottom)));
  for (int y = y0; y < y1; ++y) img.at<cv::Vec3b>(y, x) = c;
}

}  // namespace

SimCamera::SimCamera(const World& world, std::function<CameraView()> view, CameraSpec spec)
    : world_(world), view_(std::move(view)), spec_(spec) {
  focal_ = (spec_.width / 2.0) / std::tan(spec_.hfov_deg * navigation::kPi / 360.0);
  walls_ = world.map.walls;
  for (const auto& d : world.map.doors) {
    if (!d.open) walls_.push_back({d.a, d.b, world.wall_height_m});
  }
  boxes_ = world.map.furniture;
  boxes_.insert(boxes_.end(), world.clutter.begin(), world.clutter.end());
  auto load = [&](const Thing& t) {
    for (const auto& p : t.photos) {
      cv::Mat m = cv::imread(p.string(), cv::IMREAD_COLOR);
      if (m.empty()) {
        // face-api's demo photos are not in the repository: scripts/setup fetches them.
        const bool fetched = p.string().find(".cache/vision/photos") != std::string::npos;
        throw vision::CameraError("simulated camera: cannot read the photo " + p.string() +
                                  " of \"" + t.name + "\" in " + world.file.string() +
                                  (fetched ? " (scripts/setup fetches it)" : ""));
      }
      if (t.crop[2] > 0) {
        const cv::Rect crop(t.crop[0], t.crop[1], t.crop[2], t.crop[3]);
        if ((crop & cv::Rect(0, 0, m.cols, m.rows)) != crop)
          throw vision::CameraError("simulated camera: the 'crop' of \"" + t.name + "\" in " +
                                    world.file.string() + " does not fit in " + p.string() + " (" +
                                    std::to_string(m.cols) + "x" + std::to_string(m.rows) + ")");
        m = m(crop).clone();
      }
      cards_.push_back({&t, m});
      break;  // the first photo; the others are for face enrolment
    }
  };
  for (const auto& o : world.objects) load(o);
  for (const auto& p : world.people) load(p);
  depth_.resize(static_cast<std::size_t>(spec_.width));
}

std::string SimCamera::describe() const {
  return "simulated camera (head of the robot in " + world_.file.string() + ") " +
         std::to_string(spec_.width) + "x" + std::to_string(spec_.height);
}

bool SimCamera::read(vision::Frame& frame) {
  CameraView v = view_();
  render(v, frame.image);
  frame.time_us = v.time_us;
  frame.index = index_++;
  return true;
}

std::optional<cv::Rect> SimCamera::project(const Thing& thing, const CameraView& view) const {
  const Vec2 d = thing.at - view.pose.position();
  const double c = std::cos(view.pose.heading), s = std::sin(view.pose.heading);
  const double depth = d.x * c + d.y * s;     // along the heading
  const double lateral = -d.x * s + d.y * c;  // to the left
  if (depth < 0.2) return std::nullopt;
  const double horizon =
      spec_.height / 2.0 + focal_ * std::tan(view.head_deg * navigation::kPi / 180);
  const double cam_h = world_.robot.camera_height_m;
  const double h_px = focal_ * thing.size_m / depth;
  double w_px = h_px;
  for (const Card& card : cards_) {
    if (card.thing == &thing) w_px = h_px * card.photo.cols / card.photo.rows;
  }
  const double cx = spec_.width / 2.0 - focal_ * lateral / depth;
  const double bottom = horizon - focal_ * (thing.elevation_m - cam_h) / depth;
  cv::Rect r(static_cast<int>(std::lround(cx - w_px / 2)),
             static_cast<int>(std::lround(bottom - h_px)),
             std::max(1, static_cast<int>(std::lround(w_px))),
             std::max(1, static_cast<int>(std::lround(h_px))));
  if ((r & cv::Rect(0, 0, spec_.width, spec_.height)).area() == 0) return std::nullopt;
  return r;
}

void SimCamera::render(const CameraView& view, cv::Mat& out) {
  out.create(spec_.height, spec_.width, CV_8UC3);
  const navigation::Pose& p = view.pose;
  const Vec2 o = p.position();
  const double horizon =
      spec_.height / 2.0 + focal_ * std::tan(view.head_deg * navigation::kPi / 180);
  const double cam_h = world_.robot.camera_height_m, wall_h = world_.wall_height_m;
  const cv::Vec3b ceiling(236, 236, 236), wall(196, 210, 222), box(96, 112, 128);
  const cv::Vec3b floor = floor_colour(world_, o);
  const double ch = std::cos(p.heading), sh = std::sin(p.heading);
  for (int x = 0; x < spec_.width; ++x) {
    const double off = (spec_.width / 2.0 - (x + 0.5)) / focal_;  // tan of the angle, left +
    const double a = p.heading + std::atan(off);
    const Vec2 dir{std::cos(a), std::sin(a)};
    const double to_depth = dir.x * ch + dir.y * sh;  // ray length -> depth along the heading
    double hit = 1e9;
    bool x_wall = false;
    for (const auto& s : walls_) {
      const double t = navigation::ray_segment(o, dir, s.a, s.b);
      if (t < hit) {
        hit = t;
        x_wall = std::fabs(s.a.y - s.b.y) < 1e-9;
      }
    }
    const double depth = std::max(0.05, hit * to_depth);
    depth_[static_cast<std::size_t>(x)] = depth;
    const double top = horizon - focal_ * (wall_h - cam_h) / depth;
    const double foot = horizon + focal_ * cam_h / depth;
    fill_column(out, x, 0, top, ceiling);
    fill_column(out, x, top, foot, shade(wall, (x_wall ? 1.0 : 0.85) / (1 + 0.04 * depth)));
    fill_column(out, x, foot, spec_.height, floor);
    // Furniture in front of the wall: the nearest face of each box, far ones first.
    double nearest_box = depth;
    for (const auto& f : boxes_) {
      navigation::Segment sides[4];
      f.box.sides(sides);
      double t = 1e9;
      for (const auto& s : sides) t = std::min(t, navigation::ray_segment(o, dir, s.a, s.b));
      const double d = t * to_depth;
      if (d >= depth || d < 0.05) continue;
      if (d < nearest_box) nearest_box = d;
    }
    if (nearest_box < depth) {
      // Draw each box nearer than the wall, farthest first, so nearer ones cover them.
      std::vector<std::pair<double, double>> hits;  // depth, height
      for (const auto& f : boxes_) {
        navigation::Segment sides[4];
        f.box.sides(sides);
        double t = 1e9;
        for (const auto& s : sides) t = std::min(t, navigation::ray_segment(o, dir, s.a, s.b));
        const double d = t * to_depth;
        if (d < depth && d >= 0.05) hits.emplace_back(d, f.box.height);
      }
      std::sort(hits.begin(), hits.end(), [](auto& l, auto& r) { return l.first > r.first; });
      for (const auto& [d, h] : hits) {
        fill_column(out, x, horizon - focal_ * (h - cam_h) / d, horizon + focal_ * cam_h / d,
                    shade(box, 1 / (1 + 0.05 * d)));
      }
    }
  }
  // Photos, farthest first, cut by the walls in front of them.
  std::vector<std::pair<double, const Card*>> order;
  for (const Card& card : cards_) {
    const Vec2 d = card.thing->at - o;
    order.emplace_back(d.x * ch + d.y * sh, &card);
  }
  std::sort(order.begin(), order.end(), [](auto& l, auto& r) { return l.first > r.first; });
  const cv::Rect frame(0, 0, spec_.width, spec_.height);
  for (const auto& [depth, card] : order) {
    std::optional<cv::Rect> r = project(*card->thing, view);
    if (!r || r->width > 4 * spec_.width) continue;
    cv::resize(card->photo, scaled_, r->size(), 0, 0, cv::INTER_AREA);
    const cv::Rect visible = *r & frame;
    for (int x = visible.x; x < visible.x + visible.width; ++x) {
      if (depth_[static_cast<std::size_t>(x)] < depth) continue;  // a wall in front
      for (int y = visible.y; y < visible.y + visible.height; ++y)
        out.at<cv::Vec3b>(y, x) = scaled_.at<cv::Vec3b>(y - r->y, x - r->x);
    }
  }
}

}  // namespace marvin::sim
