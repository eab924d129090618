// The simulated home's costs (goals from issue 18), each next to a baseline measured in the
// same run; prints figures, never fails on time.
//
//   step     Simulator::step(10 ms) in the default home, driving with the sonar sweeping
//            (goal <= 50 us); baseline: marvin-mcu-sim's old room model (one ray, no cone,
//            no noise) stepping the same walls and furniture.
//   sonar    one noisy cone reading (5 rays) (goal <= 20 us); baseline: the old single ray.
//   camera   640x480 frames of the living room (goal >= 30 frames/s on one core); baseline:
//            clearing a 640x480 frame (cv::Mat::setTo), the least any renderer does.
//   path     A* on a 20 m x 20 m home (16 rooms of 5 m, doors between) at 5 cm cells,
//            corner to corner (goal <= 10 ms); baseline: a breadth-first flood of the same
//            grid (every free cell visited once).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <string>
#include <vector>

#include "navigation/navigator.h"
#include "room.h"
#include "sim/camera.h"
#include "sim/simulator.h"

namespace {

using Clock = std::chrono::steady_clock;

template <class F>
double median_us(F&& body, int calls) {
  std::vector<double> runs;
  for (int run = 0; run < 7; ++run) {
    auto start = Clock::now();
    for (int i = 0; i < calls; ++i) body();
    runs.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count() / calls);
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}

void print(const char* what, double us, const char* baseline, double base_us, const char* goal) {
  std::printf("%-8s %10.2f us   %-34s %10.2f us   ratio %6.1f   goal %s\n", what, us, baseline,
              base_us, us / base_us, goal);
}

marvin::mcusim::Room old_room(const marvin::sim::World& w) {
  marvin::mcusim::Room room;
  room.ceiling_m = w.wall_height_m;
  for (const auto& s : w.solid_segments())
    room.segments.push_back({s.a.x, s.a.y, s.b.x, s.b.y, s.height});
  room.start = {w.robot.start.x, w.robot.start.y,
                w.robot.start.heading * 180 / marvin::navigation::kPi};
  return room;
}

// 16 rooms of 5 m x 5 m, each joined to its east and north neighbours by a door.
marvin::navigation::FloorMap big_home() {
  marvin::navigation::FloorMap map;
  for (int i = 0; i <= 4; ++i) {
    const double c = i * 5.0;
    for (int k = 0; k < 4; ++k) {
      const double lo = k * 5.0;
      // Vertical wall x = c and horizontal wall y = c, each with a 0.9 m door in the middle
      // of every 5 m piece (outer walls closed).
      if (i == 0 || i == 4) {
        map.walls.push_back({{c, lo}, {c, lo + 5}, 2.5});
        map.walls.push_back({{lo, c}, {lo + 5, c}, 2.5});
      } else {
        map.walls.push_back({{c, lo}, {c, lo + 2.05}, 2.5});
        map.walls.push_back({{c, lo + 2.95}, {c, lo + 5}, 2.5});
        map.walls.push_back({{lo, c}, {lo + 2.05, c}, 2.5});
        map.walls.push_back({{lo + 2.95, c}, {lo + 5, c}, 2.5});
      }
    }
  }
  for (int x = 0; x < 4; ++x) {
    for (int y = 0; y < 4; ++y) {  // a table in each room, off the door lines
      map.furniture.push_back(
          {"table", {{x * 5 + 0.8, y * 5 + 0.8}, {x * 5 + 1.8, y * 5 + 1.6}, 0.75}});
    }
  }
  map.rooms.push_back({"all", {{0, 0}, {20, 0}, {20, 20}, {0, 20}}, {1, 1}});
  return map;
}

}  // namespace

int main() {
  marvin::sim::World home = marvin::sim::load_world(marvin::sim::default_world_file());

  // --- step ---
  marvin::sim::Simulator sim(home);
  auto room = old_room(home);
  marvin::mcusim::RobotPose old_pose = room.start;
  int flip = 0;
  const double step_us = median_us(
      [&] {
        // Drive in place-turning circles so the robot stays in the hall and keeps moving.
        sim.set_motor(0, (++flip / 300) % 2 == 0, 120);
        sim.set_motor(1, false, 120);
        sim.step(0.01);
      },
      20000);
  const double old_step_us =
      median_us([&] { marvin::mcusim::step_body(room, old_pose, -0.1, 0.2, 0.01); }, 20000);
  print("step", step_us, "old room model step", old_step_us, "<= 50 us");
  std::printf("         simulated time runs %.0fx faster than real time on this core\n",
              10000.0 / step_us);

  // --- sonar ---
  double sink = 0;
  int angle = 0;
  const double sonar_us = median_us(
      [&] {
        angle = (angle + 15) % 75;
        sink += sim.measure(angle).distance_m;
      },
      20000);
  const double old_sonar_us = median_us(
      [&] {
        angle = (angle + 15) % 75;
        sink += marvin::mcusim::sonar_distance_m(room, old_pose, angle);
      },
      20000);
  print("sonar", sonar_us, "old single-ray reading", old_sonar_us, "<= 20 us");

  // --- camera ---
  marvin::sim::CameraView view{{3.6, 2.6, -140 * marvin::navigation::kPi / 180}, 0, 0};
  marvin::sim::SimCamera camera(home, [&] { return view; });
  cv::Mat frame;
  const double frame_us = median_us(
      [&] {
        view.pose.heading += 0.01;
        camera.render(view, frame);
      },
      60);
  cv::Mat blank(480, 640, CV_8UC3);
  const double clear_us = median_us([&] { blank.setTo(cv::Scalar(flip++ & 255, 0, 0)); }, 200);
  print("camera", frame_us, "clearing a 640x480 frame", clear_us, ">= 30 frames/s");
  std::printf("         %.0f frames/s at 640x480\n", 1e6 / frame_us);

  // --- path ---
  marvin::navigation::FloorMap big = big_home();
  marvin::navigation::OccupancyGrid grid(big, 0.05, 0.30);
  marvin::navigation::Planner planner;
  std::size_t waypoints = 0;
  const double path_us = median_us(
      [&] {
        auto p = planner.plan(grid, {1, 3}, {19, 19});
        waypoints = p ? p->size() : 0;
      },
      5);
  const double flood_us = median_us(
      [&] {
        std::vector<std::uint8_t> seen(static_cast<std::size_t>(grid.width() * grid.height()), 0);
        std::deque<marvin::navigation::Cell> queue{grid.cell_of({1, 3})};
        std::size_t visited = 0;
        while (!queue.empty()) {
          auto c = queue.front();
          queue.pop_front();
          for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
            marvin::navigation::Cell n{c.x + dx, c.y + dy};
            if (grid.blocked(n)) continue;
            auto& s = seen[static_cast<std::size_t>(n.y * grid.width() + n.x)];
            if (s) continue;
            s = 1;
            ++visited;
            queue.push_back(n);
          }
        }
        sink += static_cast<double>(visited);
      },
      5);
  print("path", path_us, "breadth-first flood of the grid", flood_us, "<= 10000 us");
  std::printf("         %dx%d cells, %zu expanded, %zu waypoints\n", grid.width(), grid.height(),
              planner.expanded(), waypoints);
  return sink == 12345.678 ? 1 : 0;
}
