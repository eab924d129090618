// Going places: plan a path on the floor plan to a room, a place or a person, drive it with
// the body's four motions (turn in place, then forward), stop and re-plan when the sonar
// sees something in the way, give up with a reason the user understands.
//
// The same code runs on the real robot and in the simulated home: the robot's pose comes
// from a PoseSource (the simulator's odometry; on the real robot, dead reckoning, see
// README.md for its limits), the sonar from a ScanSource, and the time between control
// steps from the caller's wait function, so "stop" wakes it at once.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "devices/body.h"
#include "navigation/floor_map.h"
#include "navigation/going_places.h"
#include "navigation/occupancy_grid.h"
#include "navigation/planner.h"

namespace marvin::navigation {

struct NavigatorOptions {
  double cell_m = 0.05;
  double inflate_m = 0.30;           // robot radius 0.15 + 0.15 margin: steering error, drift
  double waypoint_m = 0.10;          // a waypoint is reached this close
  double goal_m = 0.15;              // the goal is reached this close
  double aim_deg = 6;                // turn in place while the bearing is off by more
  std::uint8_t forward_speed = 150;  // 0..255 as the base takes it
  std::uint8_t turn_speed = 90, fine_turn_speed = 45;
  double stop_m = 0.40;         // something ahead closer than this (horizontal) blocks
  double clearance_m = 0.60;    // echoes higher than this above the sonar are no obstacle
  double mark_m = 1.0;          // echoes closer than this (horizontal) go on the map
  double mark_radius_m = 0.10;  // each as a disc this wide (then inflated)
  std::chrono::milliseconds step{100};
  int max_replans = 8;
  double give_up_after_s = 120;   // robot time for one go_to
  double sonar_height_m = 0.25;   // above the floor: what a downward echo is compared with
  double step_down_stop_m = 0.5;  // a step down closer than this (horizontal) stops the robot
  double step_down_side_m = 1.0;  // a step down is marked this far to either side (an edge)
  double announce_m = 1.0;        // guide_to tells turns and obstacles this far ahead
  double time_scale = 1;          // robot seconds per wall second (GoingPlaces::time_scale)
};

class Navigator : public GoingPlaces {
 public:
  using PoseSource = std::function<Pose()>;
  // Sonar points and "now" on the same clock (ms): the points' time_ms is compared with it.
  using ScanSource = std::function<std::vector<devices::ScanPoint>()>;
  using Clock = std::function<std::int64_t()>;

  Navigator(FloorMap map, devices::Body& body, PoseSource pose, ScanSource scan, Clock now_ms,
            NavigatorOptions options = {});

  GoResult go_to(std::string_view target, const WaitFn& wait) override;
  GoResult guide_to(std::string_view target, double speed_factor, const GuideFn& on_event,
                    const WaitFn& wait) override;
  void stop() override;
  std::optional<std::string> where_am_i() override;
  double time_scale() const override { return options_.time_scale; }
  std::vector<std::string> place_names() const override;
  bool turn(double degrees, const WaitFn& wait) override;
  std::optional<Spot> locate(double bearing_deg, double distance_m) override;
  std::vector<std::string> rooms_to_search() override;
  std::optional<std::string> screen_at(double bearing_deg, double distance_m) override;
  std::optional<PlaceInfo> find_place(std::string_view name) override;
  std::optional<double> path_length_to(std::string_view name) override;

  const FloorMap& map() const { return map_; }
  // Where the robot is now (its pose source). Any thread.
  Pose pose() const { return pose_(); }
  const NavigatorOptions& options() const { return options_; }
  // The path being followed (or last followed), for pictures. Any thread.
  std::vector<Vec2> path() const;
  // Plans without moving (tests, `marvin world render`): waypoints or nullopt.
  std::optional<std::vector<Vec2>> plan(Vec2 from, Vec2 to);

 private:
  enum class Follow { kArrived, kBlocked, kCancelled, kTimeOut };
  GoResult go(std::string_view target, const WaitFn& wait, double speed_factor,
              const GuideFn* on_event);
  // Tells on_event_ (when guiding); false when it asked to stop.
  bool tell(const GuideEvent& event);
  Follow follow(const std::vector<Vec2>& path, const WaitFn& wait, std::int64_t deadline_ms);
  std::string blocked_reason(const Target& target);
  bool leg_free(Vec2 from, Vec2 to) const;
  // Turns in place until the heading is within aim_deg of `heading` (radians).
  bool turn_to(double heading, const WaitFn& wait);

  FloorMap map_;
  devices::Body& body_;
  PoseSource pose_;
  ScanSource scan_;
  Clock now_ms_;
  NavigatorOptions options_;
  OccupancyGrid grid_;
  Planner planner_;
  std::mutex run_mutex_;  // one go_to at a time
  // The thread inside go() (holding run_mutex_), else none: a guide callback on it that asks
  // path_length_to must not try a lock its own thread holds.
  std::atomic<std::thread::id> driver_{};
  mutable std::mutex path_mutex_;
  std::vector<Vec2> path_;
  std::vector<Vec2> seen_;   // where the sonar found something during this go_to
  std::vector<Vec2> drops_;  // where it found a step down (also in seen_)
  // While guiding (set by go() under run_mutex_): the speed and who is told what.
  double speed_factor_ = 1;
  const GuideFn* on_event_ = nullptr;
  std::int64_t told_obstacle_ms_ = 0;
  std::vector<Vec2> told_drops_;  // steps down told during this trip
  std::atomic<bool> stop_requested_{false};
};

}  // namespace marvin::navigation
