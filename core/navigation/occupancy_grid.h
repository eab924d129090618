// The floor plan as square cells (default 5 cm): occupied by a wall or furniture, and
// "blocked" for the robot's centre when closer to an occupied cell than the inflation
// radius (the robot's radius plus a margin), so a path through unblocked cells keeps the
// whole body clear. Obstacles the sonar found are added on top and can be cleared again.
#pragma once

#include <cstdint>
#include <vector>

#include "navigation/floor_map.h"

namespace marvin::navigation {

struct Cell {
  int x = 0, y = 0;
  bool operator==(const Cell&) const = default;
};

class OccupancyGrid {
 public:
  OccupancyGrid(const FloorMap& map, double cell_m, double inflate_m);

  int width() const { return width_; }
  int height() const { return height_; }
  double cell_m() const { return cell_m_; }
  bool inside(Cell c) const { return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_; }
  Cell cell_of(Vec2 p) const;
  Vec2 centre_of(Cell c) const;
  // Outside the grid counts as occupied and blocked.
  bool occupied(Cell c) const { return !inside(c) || raw_[index(c)] != 0; }
  bool blocked(Cell c) const { return !inside(c) || inflated_[index(c)] != 0; }

  // An obstacle the sonar saw: a disc of `radius_m` at `at`, inflated like the rest.
  void add_obstacle(Vec2 at, double radius_m);
  // Forgets every added obstacle.
  void clear_obstacles();
  bool has_obstacles() const { return !added_.empty(); }
  // Whether a wall or furniture of the floor plan (not an added obstacle) lies within
  // `radius_m` of `at`.
  bool near_static(Vec2 at, double radius_m) const;

 private:
  std::size_t index(Cell c) const {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(c.x);
  }
  void mark(Cell c, std::vector<std::uint8_t>& raw, std::vector<std::uint8_t>& inflated);

  double cell_m_, inflate_m_;
  Vec2 origin_;
  int width_ = 0, height_ = 0;
  std::vector<Cell> disc_;  // offsets within the inflation radius
  std::vector<std::uint8_t> raw_, inflated_, static_raw_, static_inflated_;
  std::vector<std::pair<Vec2, double>> added_;
};

}  // namespace marvin::navigation
