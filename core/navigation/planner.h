// Shortest paths on an OccupancyGrid: A* over 8-connected cells (octile distance, no
// corner cutting past blocked cells), then shortened to the waypoints a robot that turns
// in place needs (each leg a straight line through unblocked cells).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "navigation/occupancy_grid.h"

namespace marvin::navigation {

class Planner {
 public:
  // Keeps its buffers between plans: no allocation once sized for a grid.
  Planner() = default;

  // Waypoints from `from` to `to` (the first is `from`, the last the goal), or nullopt when
  // no path exists. A start inside a blocked cell (the robot too close to something) starts
  // from the nearest free cell within 0.5 m; a goal inside one (a person on the sofa) ends
  // at the nearest free cell within 1 m of it.
  std::optional<std::vector<Vec2>> plan(const OccupancyGrid& grid, Vec2 from, Vec2 to);

  // Cells A* expanded in the last plan (for the benchmark and tests).
  std::size_t expanded() const { return expanded_; }

 private:
  std::optional<Cell> nearest_free(const OccupancyGrid& grid, Cell c, double within_m);
  bool line_free(const OccupancyGrid& grid, Cell a, Cell b) const;

  std::vector<float> g_;
  std::vector<std::int32_t> parent_;
  std::vector<std::uint32_t> stamp_;  // g_/parent_ valid when stamp_ == run_
  std::vector<std::uint8_t> closed_;
  std::uint32_t run_ = 0;
  std::vector<std::pair<float, std::int32_t>> heap_;
  std::size_t expanded_ = 0;
};

}  // namespace marvin::navigation
