// The simulated camera (implements vision::Camera): what the robot's head would see from
// its pose and tilt. Walls and furniture are drawn by casting one ray per image column
// (room colours, shaded by direction and distance); the real photos of the objects and
// people in the field of view are pasted as upright cards scaled by distance and cut by
// the walls in front of them, so the real detectors run on real pixels.
//
// Simplifications (README.md): the head's tilt shifts the horizon instead of rotating
// the image plane; photos are cut by walls (per column) but not by furniture.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/world.h"
#include "vision/camera.h"

namespace marvin::sim {

struct CameraSpec {
  int width = 640, height = 480;
  double hfov_deg = 60;
};

// Where the camera is when a frame is taken.
struct CameraView {
  navigation::Pose pose;
  double head_deg = 0;  // tilt above level
  std::int64_t time_us = 0;
};

class SimCamera : public vision::Camera {
 public:
  // Loads the photos of the world's objects and people (CameraError naming a photo that
  // cannot be read). `view` gives the pose for each read().
  SimCamera(const World& world, std::function<CameraView()> view, CameraSpec spec = {});

  bool read(vision::Frame& frame) override;
  std::string describe() const override;

  // One picture from `view` into `out` (reused when its size matches).
  void render(const CameraView& view, cv::Mat& out);
  // Where a thing's photo lands in the picture (before cutting by walls), or nullopt when
  // it is behind the camera or outside the picture.
  std::optional<cv::Rect> project(const Thing& thing, const CameraView& view) const;

 private:
  struct Card {
    const Thing* thing;
    cv::Mat photo;
  };
  const World& world_;
  std::function<CameraView()> view_;
  CameraSpec spec_;
  double focal_;
  std::vector<navigation::Segment> walls_;
  std::vector<navigation::Furniture> boxes_;
  std::vector<Card> cards_;
  std::vector<double> depth_;  // per column: the nearest wall
  cv::Mat scaled_;
  std::uint64_t index_ = 0;
};

}  // namespace marvin::sim
