#include "navigation/occupancy_grid.h"

#include <algorithm>
#include <cmath>

namespace marvin::navigation {

OccupancyGrid::OccupancyGrid(const FloorMap& map, double cell_m, double inflate_m)
    : cell_m_(cell_m), inflate_m_(inflate_m) {
  Box b = map.bounds();
  // One inflation radius of margin around the plan, so nothing falls off the grid.
  origin_ = {b.min.x - inflate_m - cell_m, b.min.y - inflate_m - cell_m};
  width_ = static_cast<int>(std::ceil((b.max.x - origin_.x + inflate_m + cell_m) / cell_m)) + 1;
  height_ = static_cast<int>(std::ceil((b.max.y - origin_.y + inflate_m + cell_m) / cell_m)) + 1;
  const auto n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  static_raw_.assign(n, 0);
  static_inflated_.assign(n, 0);
  const int r = static_cast<int>(std::ceil(inflate_m / cell_m));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (std::hypot(dx, dy) * cell_m <= inflate_m) disc_.push_back({dx, dy});
    }
  }
  auto rasterise = [&](Vec2 a, Vec2 c) {
    const double len = distance(a, c);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (cell_m * 0.5))));
    for (int i = 0; i <= steps; ++i) {
      mark(cell_of(a + (c - a) * (static_cast<double>(i) / steps)), static_raw_, static_inflated_);
    }
  };
  for (const Segment& s : map.walls) rasterise(s.a, s.b);
  for (const Furniture& f : map.furniture) {
    Cell lo = cell_of(f.box.min), hi = cell_of(f.box.max);
    for (int y = lo.y; y <= hi.y; ++y) {
      for (int x = lo.x; x <= hi.x; ++x) mark({x, y}, static_raw_, static_inflated_);
    }
  }
  raw_ = static_raw_;
  inflated_ = static_inflated_;
}

void OccupancyGrid::mark(Cell c, std::vector<std::uint8_t>& raw,
                         std::vector<std::uint8_t>& inflated) {
  if (!inside(c)) return;
  if (raw[index(c)]) return;
  raw[index(c)] = 1;
  for (Cell d : disc_) {
    Cell n{c.x + d.x, c.y + d.y};
    if (inside(n)) inflated[index(n)] = 1;
  }
}

Cell OccupancyGrid::cell_of(Vec2 p) const {
  return {static_cast<int>(std::floor((p.x - origin_.x) / cell_m_)),
          static_cast<int>(std::floor((p.y - origin_.y) / cell_m_))};
}

Vec2 OccupancyGrid::centre_of(Cell c) const {
  return {origin_.x + (c.x + 0.5) * cell_m_, origin_.y + (c.y + 0.5) * cell_m_};
}

void OccupancyGrid::add_obstacle(Vec2 at, double radius_m) {
  added_.emplace_back(at, radius_m);
  const int r = static_cast<int>(std::ceil(radius_m / cell_m_));
  Cell c = cell_of(at);
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (std::hypot(dx, dy) * cell_m_ <= radius_m) mark({c.x + dx, c.y + dy}, raw_, inflated_);
    }
  }
}

bool OccupancyGrid::near_static(Vec2 at, double radius_m) const {
  const int r = static_cast<int>(std::ceil(radius_m / cell_m_));
  const Cell c = cell_of(at);
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const Cell n{c.x + dx, c.y + dy};
      if (std::hypot(dx, dy) * cell_m_ > radius_m) continue;
      if (!inside(n) || static_raw_[index(n)] != 0) return true;
    }
  }
  return false;
}

void OccupancyGrid::clear_obstacles() {
  added_.clear();
  raw_ = static_raw_;
  inflated_ = static_inflated_;
}

}  // namespace marvin::navigation
