// The simulated base and sonar against closed-form motion and geometry.
#include "sim/simulator.h"

#include <doctest/doctest.h>

#include <cmath>

#include "sim/sim_runner.h"

using marvin::navigation::kPi;
using marvin::sim::parse_world;
using marvin::sim::SimOptions;
using marvin::sim::Simulator;

namespace {

// A 10 m x 6 m empty room; the robot at (2, 3) facing east (+x): the east wall 8 m ahead,
// the north and south walls 3 m to each side.
marvin::sim::World empty_room(const std::string& furniture = "") {
  return parse_world(R"({"format": "marvin-world", "version": 1, "wall_height_m": 2.5,
    "rooms": [{"name": "hall", "outline": [[0,0],[10,0],[10,6],[0,6]]}],
    )" + furniture + R"(
    "robot": {"start": [2, 3], "heading_deg": 0, "track_m": 0.25, "max_speed_m_s": 0.4,
              "accel_m_s2": 1000, "sonar_height_m": 0.25}})",
                     "/tmp/empty.json");
}

SimOptions exact() {
  SimOptions o;
  o.odometry_noise = 0;
  o.sonar_noise_m = 0;
  o.sonar_dropout = 0;
  return o;
}

}  // namespace

TEST_CASE("straight drive covers v t; turning in place turns 2 v t / track") {
  Simulator sim(empty_room(), exact());
  sim.set_motor(0, false, 255);
  sim.set_motor(1, false, 255);
  sim.step(2.0);
  CHECK(sim.pose().x == doctest::Approx(2 + 0.4 * 2.0).epsilon(0.01));
  CHECK(sim.pose().y == doctest::Approx(3));
  sim.set_motor(0, true, 51);  // left backward, right forward: turn left in place
  sim.set_motor(1, false, 51);
  const double x = sim.pose().x;
  sim.step(1.0);
  const double v = 51 / 255.0 * 0.4, w = 2 * v / 0.25;
  CHECK(sim.pose().heading == doctest::Approx(w * 1.0).epsilon(0.02));
  CHECK(sim.pose().x == doctest::Approx(x).epsilon(0.001));
}

TEST_CASE("an arc follows the closed-form circle") {
  Simulator sim(empty_room(), exact());
  sim.set_motor(0, false, 100);
  sim.set_motor(1, false, 200);
  sim.step(1.5);
  const double vl = 100 / 255.0 * 0.4, vr = 200 / 255.0 * 0.4;
  const double v = (vl + vr) / 2, w = (vr - vl) / 0.25, t = 1.5;
  const double r = v / w;
  CHECK(sim.pose().heading == doctest::Approx(w * t).epsilon(0.01));
  CHECK(sim.pose().x == doctest::Approx(2 + r * std::sin(w * t)).epsilon(0.01));
  CHECK(sim.pose().y == doctest::Approx(3 + r * (1 - std::cos(w * t))).epsilon(0.01));
}

TEST_CASE("acceleration is limited") {
  auto world = empty_room();
  world.robot.accel_m_s2 = 1.0;
  Simulator sim(world, exact());
  sim.set_motor(0, false, 255);
  sim.set_motor(1, false, 255);
  sim.step(0.2);
  CHECK(sim.left_m_s() == doctest::Approx(0.2));
  // Distance under constant acceleration: a t^2 / 2.
  CHECK(sim.pose().x - 2 == doctest::Approx(0.5 * 1.0 * 0.04).epsilon(0.1));
}

TEST_CASE("sonar distances match the geometry, capped at 2.5 m") {
  Simulator sim(
      empty_room(
          R"("furniture": [{"name": "box", "min": [3, 2.5], "max": [3.5, 3.5], "height_m": 0.5}],)"),
      exact());
  // Straight ahead: the box 1 m away.
  CHECK(sim.sonar_geometry_m(sim.pose(), 0) == doctest::Approx(1.0));
  // Angled up 30 degrees: the ray is 0.25 + 1 * tan 30 = 0.83 m high at the box: over it.
  // Then the ceiling: (2.5 - 0.25) / sin 30 = 4.5 m, beyond the sonar's range.
  CHECK(sim.sonar_geometry_m(sim.pose(), 30) == doctest::Approx(4.5));
  CHECK_FALSE(sim.measure(30).echo);
  CHECK(sim.measure(30).distance_m == 2.5);
  // Straight up: the ceiling 2.25 m above the sonar.
  CHECK(sim.sonar_geometry_m(sim.pose(), 90) == doctest::Approx(2.25));
  // Facing the south wall (3 m): nothing within 2.5 m.
  marvin::navigation::Pose south{2, 3, -kPi / 2};
  CHECK(sim.sonar_geometry_m(south, 0) == doctest::Approx(3.0));
  // Near the south wall, at 60 degrees to it: the cone's nearest ray is 7.5 degrees
  // closer to the wall's normal: 1 / cos(60 - 7.5).
  marvin::navigation::Pose slanted{2, 1, -kPi / 2 + kPi / 3};
  CHECK(sim.sonar_geometry_m(slanted, 0) ==
        doctest::Approx(1.0 / std::cos((60 - 7.5) * kPi / 180)).epsilon(0.001));
}

TEST_CASE("the sonar sweeps at most 69 readings a second, noise is seeded") {
  SimOptions noisy;
  noisy.seed = 7;
  Simulator a(empty_room(), noisy), b(empty_room(), noisy);
  a.set_sweep(2, 0, 0, 15);  // fixed straight ahead: one reading per echo window
  b.set_sweep(2, 0, 0, 15);
  a.step(10);
  b.step(10);
  CHECK(a.sonar_count() <= 690);
  CHECK(a.sonar_count() >= 680);
  CHECK(a.latest_sonar().at(0).distance_m == b.latest_sonar().at(0).distance_m);
  // The default sweep 0..60 by 15 waits for the servo: 15 degrees = 35 ms + the window.
  Simulator c(empty_room(), noisy);
  c.step(10);
  CHECK(c.sonar_count() < 210);
  CHECK(c.latest_sonar().size() == 5);
}

TEST_CASE("the robot never drives through a wall: the collision stops and is reported") {
  Simulator sim(empty_room(), exact());
  int reported = 0;
  sim.on_collision([&](const marvin::navigation::Pose&) { ++reported; });
  sim.set_motor(0, false, 255);
  sim.set_motor(1, false, 255);
  for (int i = 0; i < 3000; ++i) {
    sim.step(0.01);
    REQUIRE(sim.pose().x <= 10 - 0.15 + 1e-9);
  }
  CHECK(sim.collisions() == 1);
  CHECK(reported == 1);
  CHECK(sim.left_m_s() == 0);
  CHECK(sim.pose().x > 9.5);
}

TEST_CASE("odometry drifts from the truth with noise, identically for one seed") {
  SimOptions o;
  o.seed = 3;
  Simulator a(empty_room(), o), b(empty_room(), o);
  for (Simulator* s : {&a, &b}) {
    s->set_motor(0, false, 200);
    s->set_motor(1, false, 180);
    s->step(5);
  }
  CHECK(a.odometry().x == b.odometry().x);
  CHECK(a.odometry().x != a.pose().x);
  CHECK(std::fabs(a.odometry().x - a.pose().x) < 0.1);
}

TEST_CASE("SimRunner moves from Body commands with the firmware's wheel codes") {
  marvin::sim::SimRunner runner(empty_room(), exact(), 1.0);
  runner.move(marvin::devices::Direction::kForward, 255, std::chrono::milliseconds(1000));
  runner.advance(std::chrono::milliseconds(2000));
  CHECK(runner.true_pose().x == doctest::Approx(2.4).epsilon(0.01));  // the move ended at 1 s
  runner.move(marvin::devices::Direction::kLeft, 100, std::chrono::milliseconds(500));
  runner.advance(std::chrono::milliseconds(500));
  CHECK(runner.true_pose().heading > 0.5);
}
