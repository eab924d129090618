#include "navigation/planner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>

namespace marvin::navigation {

std::optional<Cell> Planner::nearest_free(const OccupancyGrid& grid, Cell c, double within_m) {
  if (!grid.blocked(c)) return c;
  const int r = static_cast<int>(std::ceil(within_m / grid.cell_m()));
  std::optional<Cell> best;
  double best_d = 1e18;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      Cell n{c.x + dx, c.y + dy};
      double d = std::hypot(dx, dy);
      if (d > r || d >= best_d || grid.blocked(n)) continue;
      best = n;
      best_d = d;
    }
  }
  return best;
}

// Supercover walk from a to b: every cell the line touches must be unblocked.
bool Planner::line_free(const OccupancyGrid& grid, Cell a, Cell b) const {
  int dx = std::abs(b.x - a.x), dy = std::abs(b.y - a.y);
  int sx = a.x < b.x ? 1 : -1, sy = a.y < b.y ? 1 : -1;
  int x = a.x, y = a.y;
  int err = dx - dy;
  while (true) {
    if (grid.blocked({x, y})) return false;
    if (x == b.x && y == b.y) return true;
    int e2 = 2 * err;
    if (e2 > -dy && e2 < dx) {  // diagonal step: both side cells must be free too
      if (grid.blocked({x + sx, y}) || grid.blocked({x, y + sy})) return false;
    }
    if (e2 > -dy) {
      err -= dy;
      x += sx;
    }
    if (e2 < dx) {
      err += dx;
      y += sy;
    }
  }
}

std::optional<std::vector<Vec2>> Planner::plan(const OccupancyGrid& grid, Vec2 from, Vec2 to) {
  expanded_ = 0;
  std::optional<Cell> start = nearest_free(grid, grid.cell_of(from), 0.5);
  std::optional<Cell> goal = nearest_free(grid, grid.cell_of(to), 1.0);
  if (!start || !goal) return std::nullopt;
  const int w = grid.width();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(grid.height());
  if (g_.size() != n) {
    g_.assign(n, 0);
    parent_.assign(n, -1);
    stamp_.assign(n, 0);
    closed_.assign(n, 0);
    run_ = 0;
  }
  if (++run_ == 0) {  // the stamp wrapped: start over
    std::fill(stamp_.begin(), stamp_.end(), 0);
    run_ = 1;
  }
  auto idx = [w](Cell c) { return c.y * w + c.x; };
  auto h = [&](Cell c) {
    float dx = static_cast<float>(std::abs(c.x - goal->x));
    float dy = static_cast<float>(std::abs(c.y - goal->y));
    return std::max(dx, dy) + 0.41421356f * std::min(dx, dy);
  };
  heap_.clear();
  const std::int32_t s = idx(*start), t = idx(*goal);
  g_[static_cast<std::size_t>(s)] = 0;
  parent_[static_cast<std::size_t>(s)] = -1;
  stamp_[static_cast<std::size_t>(s)] = run_;
  closed_[static_cast<std::size_t>(s)] = 0;
  heap_.emplace_back(-h(*start), s);
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  static constexpr float kCost[8] = {1,           1,           1,           1,
                                     1.41421356f, 1.41421356f, 1.41421356f, 1.41421356f};
  bool found = false;
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end());
    const std::int32_t cur = heap_.back().second;
    heap_.pop_back();
    const auto ucur = static_cast<std::size_t>(cur);
    if (closed_[ucur] && stamp_[ucur] == run_) continue;
    closed_[ucur] = 1;
    ++expanded_;
    if (cur == t) {
      found = true;
      break;
    }
    const Cell c{cur % w, cur / w};
    for (int k = 0; k < 8; ++k) {
      Cell nb{c.x + kDx[k], c.y + kDy[k]};
      if (grid.blocked(nb)) continue;
      if (k >= 4 && (grid.blocked({c.x + kDx[k], c.y}) || grid.blocked({c.x, c.y + kDy[k]})))
        continue;  // no squeezing diagonally between two blocked cells
      const auto un = static_cast<std::size_t>(idx(nb));
      const float g = g_[ucur] + kCost[k];
      if (stamp_[un] == run_) {
        if (closed_[un] || g >= g_[un]) continue;
      } else {
        stamp_[un] = run_;
        closed_[un] = 0;
      }
      g_[un] = g;
      parent_[un] = cur;
      heap_.emplace_back(-(g + h(nb)), static_cast<std::int32_t>(un));
      std::push_heap(heap_.begin(), heap_.end());
    }
  }
  if (!found) return std::nullopt;
  std::vector<Cell> cells;
  for (std::int32_t i = t; i != -1; i = parent_[static_cast<std::size_t>(i)]) {
    cells.push_back({i % w, i / w});
  }
  std::reverse(cells.begin(), cells.end());
  // Shorten: from each kept cell jump to the farthest cell still in plain sight.
  std::vector<Vec2> out{from};
  std::size_t i = 0;
  while (i + 1 < cells.size()) {
    std::size_t j = i + 1;
    while (j + 1 < cells.size() && line_free(grid, cells[i], cells[j + 1])) ++j;
    out.push_back(grid.centre_of(cells[j]));
    i = j;
  }
  if (out.size() == 1) out.push_back(grid.centre_of(*goal));
  return out;
}

}  // namespace marvin::navigation
