// Going places in the simulated home: the planner finds a path or reports none; the
// navigator drives there on odometry without touching anything; a blocked door is named.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "navigation/dead_reckoning.h"
#include "navigation/navigator.h"
#include "navigation/planner.h"
#include "sim/sim_runner.h"

using marvin::navigation::GoResult;
using marvin::navigation::Navigator;
using marvin::navigation::OccupancyGrid;
using marvin::navigation::Planner;
using marvin::navigation::Vec2;

namespace {

marvin::sim::World home() { return marvin::sim::load_world(marvin::sim::default_world_file()); }

// The navigator on the simulated robot, stepped by hand: fully deterministic.
struct Rig {
  explicit Rig(marvin::sim::World world)
      : runner(std::move(world), marvin::sim::SimOptions{}, 1.0),
        nav(
            runner.floor_map(), runner, [this] { return runner.odometry(); },
            [this] { return runner.sim_scan(); }, [this] { return runner.now_ms(); }) {}
  GoResult go(const std::string& where) {
    return nav.go_to(where, [this](std::chrono::milliseconds ms) {
      return runner.wait(ms, [] { return false; });
    });
  }
  marvin::sim::SimRunner runner;
  Navigator nav;
};

double min_clearance_during(Rig& rig, const std::string& where, GoResult* result) {
  double least = 1e9;
  std::function<bool(std::chrono::milliseconds)> wait = [&](std::chrono::milliseconds ms) {
    bool cancelled = rig.runner.wait(ms, [] { return false; });
    rig.runner.inspect(
        [&](const marvin::sim::Simulator& s) { least = std::min(least, s.clearance_m(s.pose())); });
    return cancelled;
  };
  *result = rig.nav.go_to(where, wait);
  return least;
}

}  // namespace

TEST_CASE("the planner finds a path through the doors, or reports none") {
  auto w = home();
  OccupancyGrid grid(w.map, 0.05, 0.25);
  Planner planner;
  auto path = planner.plan(grid, {5, 1.5}, w.map.find("kitchen")->at);
  REQUIRE(path.has_value());
  CHECK(path->size() >= 3);
  // Every leg stays clear of the walls by the inflation radius (checked at 1 cm).
  for (std::size_t i = 1; i < path->size(); ++i) {
    Vec2 a = (*path)[i - 1], b = (*path)[i];
    for (double t = 0; t <= 1; t += 0.01) {
      Vec2 p = a + (b - a) * t;
      if (i == 1 && t < 0.05) continue;
      for (const auto& s : w.map.walls)
        REQUIRE(marvin::navigation::point_segment_distance(p, s.a, s.b) > 0.15);
    }
  }
  // The kitchen door shut by a box: the kitchen cannot be reached.
  w.map.furniture.push_back({"box", {{5.7, 1.4}, {6.3, 2.6}, 1.0}});
  OccupancyGrid shut(w.map, 0.05, 0.25);
  CHECK_FALSE(planner.plan(shut, {5, 1.5}, w.map.find("kitchen")->at).has_value());
  CHECK(planner.plan(shut, {5, 1.5}, w.map.find("bedroom")->at).has_value());
}

TEST_CASE("go to the kitchen: arrives in the kitchen without touching anything") {
  Rig rig(home());
  GoResult r;
  const double least = min_clearance_during(rig, "the kitchen", &r);
  CHECK(r.arrived());
  CHECK(r.reason == "");
  rig.runner.inspect([](const marvin::sim::Simulator& s) {
    CHECK(s.collisions() == 0);
    CHECK(s.world().map.room_at(s.pose().position())->name == "kitchen");
  });
  CHECK(least > 0.15);
  CHECK(rig.nav.where_am_i() == std::optional<std::string>("kitchen"));
}

TEST_CASE("places and people: the bedside table, Anna on the sofa") {
  Rig rig(home());
  CHECK(rig.go("the bedside table").arrived());
  CHECK(rig.nav.where_am_i() == std::optional<std::string>("bedroom"));
  CHECK(rig.go("Anna").arrived());
  CHECK(rig.nav.where_am_i() == std::optional<std::string>("living room"));
  rig.runner.inspect([](const marvin::sim::Simulator& s) { CHECK(s.collisions() == 0); });
}

TEST_CASE("how far: the length of the path the robot would drive, without driving it") {
  Rig rig(home());
  // From the hall (5, 1.5) through the kitchen door (6, 2) to the kitchen's spot (8, 3):
  // longer than the straight line (3.35 m), shorter than a detour through another room.
  const std::optional<double> kitchen = rig.nav.path_length_to("the kitchen");
  REQUIRE(kitchen.has_value());
  CHECK(*kitchen > 3.35);
  CHECK(*kitchen < 4.5);
  CHECK_FALSE(rig.nav.path_length_to("the garage").has_value());
  CHECK(rig.runner.now_ms() == 0);  // asking moved nothing
  // Asked while driving (here from the drive's own thread, as a guide callback would): no
  // length, and the drive goes on.
  int asked = 0, answered = 0;
  GoResult to_kitchen = rig.nav.go_to("the kitchen", [&](std::chrono::milliseconds ms) {
    ++asked;
    if (rig.nav.path_length_to("the bedroom")) ++answered;
    return rig.runner.wait(ms, [] { return false; });
  });
  REQUIRE(to_kitchen.arrived());
  CHECK(asked > 0);
  CHECK(answered == 0);
  CHECK(*rig.nav.path_length_to("kitchen") < 0.5);
  // A box in the kitchen door: no way into the kitchen, so no length.
  auto w = home();
  w.map.furniture.push_back({"box", {{5.7, 1.4}, {6.3, 2.6}, 1.0}});
  Rig shut(std::move(w));
  CHECK_FALSE(shut.nav.path_length_to("kitchen").has_value());
  CHECK(shut.nav.path_length_to("bedroom").has_value());
}

TEST_CASE("an unknown place is refused without moving") {
  Rig rig(home());
  GoResult r = rig.go("the garage");
  CHECK(r.outcome == GoResult::Outcome::kUnknownPlace);
  CHECK(r.reason == "I don't know where the garage is");
  CHECK(rig.runner.now_ms() == 0);
}

TEST_CASE("clutter in the kitchen door: the sonar sees it, the robot gives up naming the door") {
  auto w = home();
  w.clutter.push_back({"laundry basket", {{5.75, 1.5}, {6.25, 2.5}, 0.6}});
  Rig rig(std::move(w));
  GoResult r = rig.go("kitchen");
  CHECK(r.outcome == GoResult::Outcome::kGaveUp);
  CHECK(r.reason == "the kitchen door is blocked");
  rig.runner.inspect([](const marvin::sim::Simulator& s) {
    CHECK(s.collisions() == 0);
    CHECK(s.world().map.room_at(s.pose().position())->name == "hall");
  });
}

TEST_CASE("stop ends a go_to at once and the wheels stop") {
  Rig rig(home());
  int steps = 0;
  GoResult r = rig.nav.go_to("kitchen", [&](std::chrono::milliseconds ms) {
    rig.runner.wait(ms, [] { return false; });
    return ++steps == 20;  // the user says "stop" after 2 s
  });
  CHECK(r.outcome == GoResult::Outcome::kCancelled);
  rig.runner.advance(std::chrono::milliseconds(500));  // the base decelerates
  rig.runner.inspect([](const marvin::sim::Simulator& s) {
    CHECK(s.left_m_s() == 0);
    CHECK(s.right_m_s() == 0);
  });
}

TEST_CASE("a box the map does not show: the sonar sees it, the robot re-plans around it") {
  auto w = marvin::sim::parse_world(R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[6,0],[6,4],[0,4]]}],
    "clutter": [{"name": "box", "min": [2.7, 1.5], "max": [3.3, 2.5], "height_m": 0.5}],
    "places": [{"name": "the window", "at": [5, 2], "room": "hall"}],
    "robot": {"start": [1, 2], "heading_deg": 0}})",
                                    "/tmp/replan.json");
  Rig rig(std::move(w));
  // The map has no box: the first plan is the straight line.
  auto first = rig.nav.plan({1, 2}, {5, 2});
  REQUIRE(first);
  CHECK(first->size() == 2);
  GoResult r;
  const double least = min_clearance_during(rig, "the window", &r);
  CHECK(r.arrived());
  CHECK(rig.nav.path().size() > 2);  // the path it finished on goes around the box
  CHECK(least > 0.15);
  rig.runner.inspect([](const marvin::sim::Simulator& s) {
    CHECK(s.collisions() == 0);
    CHECK(marvin::navigation::distance(s.pose().position(), {5, 2}) < 0.25);
  });
}

TEST_CASE("dead reckoning of the commands sent follows the simulated base it drives") {
  auto w = home();
  const marvin::navigation::Pose start = w.robot.start;
  marvin::sim::SimOptions exact;
  exact.odometry_noise = 0;
  marvin::sim::SimRunner base(w, exact, 1.0);
  auto now = std::chrono::steady_clock::time_point{};
  marvin::navigation::DeadReckoning dr(base, {0.4, 0.25, 1.0}, start, [&] { return now; });
  auto run = [&](int ms) {
    base.advance(std::chrono::milliseconds(ms));
    now += std::chrono::milliseconds(ms);
  };
  dr.move(marvin::devices::Direction::kForward, 200, std::chrono::milliseconds(1500));
  run(2000);
  dr.move(marvin::devices::Direction::kLeft, 90, std::chrono::milliseconds(700));
  run(1000);
  dr.move(marvin::devices::Direction::kForward, 120, std::chrono::milliseconds(800));
  run(400);
  dr.stop();
  run(600);
  const auto truth = base.true_pose(), guess = dr.pose();
  CHECK(marvin::navigation::distance(truth.position(), start.position()) > 0.5);
  CHECK(marvin::navigation::distance(truth.position(), guess.position()) < 0.02);
  CHECK(std::fabs(marvin::navigation::wrap_angle(truth.heading - guess.heading)) < 0.03);
}

TEST_CASE("dead reckoning of wheel commands: a drive lasts while its frames come, as on the MCU") {
  // The serial base's form: each command holds for the deadman (300 ms) unless another comes,
  // as the MCU's deadman holds it; a host that stops refreshing (it stalled) moves the pose no
  // further than the body moved. Base {0.4 m/s at 255, track 0.25 m, 1 m/s^2}, so from rest
  // at speed 255: 0.4 s to full speed (0.08 m), 0.4 s to stop again (0.08 m).
  using marvin::devices::Direction;
  using marvin::devices::MotorBase;
  using namespace std::chrono_literals;
  struct NoBody : marvin::devices::Body {
    void move(Direction, std::uint8_t, std::chrono::milliseconds) override {}
    void stop() override {}
    void tilt_head(int) override {}
    std::vector<marvin::devices::ScanPoint> latest_scan() override { return {}; }
    void set_light(marvin::devices::Light) override {}
  } body;
  const marvin::navigation::Pose start{1, 2, 0};
  const auto t0 = std::chrono::steady_clock::time_point{} + 1h;
  auto now = t0;
  auto travelled = [&](marvin::navigation::DeadReckoning& dr) {
    now = t0 + 10s;  // long after every command
    const auto p = dr.pose();
    CHECK(std::fabs(p.y - start.y) < 1e-9);  // straight: both sides alike
    return p.x - start.x;
  };
  auto reckoning = [&] {
    now = t0;
    return std::make_unique<marvin::navigation::DeadReckoning>(
        body, marvin::navigation::BaseSpec{0.4, 0.25, 1.0}, start, [&] { return now; });
  };

  SUBCASE("one frame and no more: 0.3 s of drive, then the stop") {
    auto dr = reckoning();
    dr->wheel_command({t0, Direction::kForward, 255}, MotorBase::kDeadman);
    // Up to 0.3 m/s in 0.3 s (0.045 m), down again in 0.3 s (0.045 m).
    CHECK(travelled(*dr) == doctest::Approx(0.09).epsilon(0.01));
  }
  SUBCASE("refreshed for 1 s, then the host stalls: the drive ends 0.3 s after the last frame") {
    auto dr = reckoning();
    for (int ms = 0; ms <= 1000; ms += 100)
      dr->wheel_command({t0 + std::chrono::milliseconds(ms), Direction::kForward, 255},
                        MotorBase::kDeadman);
    // 0.08 m up to speed, 0.9 s at 0.4 m/s (0.36 m) until 1.3 s, 0.08 m to stop.
    CHECK(travelled(*dr) == doctest::Approx(0.52).epsilon(0.01));
  }
  SUBCASE("refreshed for 1 s, then stopped: the drive ends at the stop") {
    auto dr = reckoning();
    for (int ms = 0; ms < 1000; ms += 100)
      dr->wheel_command({t0 + std::chrono::milliseconds(ms), Direction::kForward, 255},
                        MotorBase::kDeadman);
    dr->wheel_command({t0 + 1s, Direction::kForward, 0}, MotorBase::kDeadman);
    // 0.08 m up to speed, 0.6 s at 0.4 m/s (0.24 m), 0.08 m to stop.
    CHECK(travelled(*dr) == doctest::Approx(0.40).epsilon(0.01));
  }
  SUBCASE("frames again after the stall: the body drove before it and after it, not during") {
    auto dr = reckoning();
    for (int ms : {0, 100, 200, 300, 400, 500, 2000, 2100, 2200, 2300, 2400, 2500})
      dr->wheel_command({t0 + std::chrono::milliseconds(ms), Direction::kForward, 255},
                        MotorBase::kDeadman);
    // Each burst: 0.08 m up to speed, 0.4 s at 0.4 m/s (0.16 m) until 0.8 s, 0.08 m to stop.
    CHECK(travelled(*dr) == doctest::Approx(2 * 0.32).epsilon(0.01));
  }
}

TEST_CASE("the names a user can say after \"go to\"") {
  Rig rig(home());
  const auto names = rig.nav.place_names();
  for (const char* want : {"kitchen", "the kitchen", "living room", "the sofa", "sofa",
                           "the front door", "Anna", "me"})
    CHECK(std::find(names.begin(), names.end(), want) != names.end());
}

// Guard mode takes a face at a screen the map knows for a picture (skills/guard.h): the robot
// 1.6 m in front of the default home's tv stand, marked a screen here, facing it.
TEST_CASE("screen_at: straight ahead at the tv's distance is the tv; beside it or close is not") {
  marvin::sim::World world = home();
  for (auto& f : world.map.furniture) f.screen = f.name == "tv stand";
  world.robot.start = {1.0, 2.9, 3.14159265358979 / 2};
  Rig rig(std::move(world));
  CHECK(rig.nav.screen_at(0, 1.6) == std::optional<std::string>("tv stand"));
  CHECK(rig.nav.screen_at(-15, 2.0) == std::optional<std::string>("tv stand"));  // its right end
  CHECK_FALSE(rig.nav.screen_at(45, 1.8).has_value());         // beside it (to the left, x < 0)
  CHECK_FALSE(rig.nav.screen_at(0, 0.6).has_value());          // between the robot and the tv
  CHECK_FALSE(rig.nav.screen_at(180, 1.6).has_value());        // behind the robot
  CHECK_FALSE(Rig(home()).nav.screen_at(0, 1.6).has_value());  // no screen on the map
}
