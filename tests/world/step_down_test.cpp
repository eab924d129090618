// A step down: the sweep's classification (wall / low obstacle / step down / clear) from
// D_x = D cos θ, D_y = D sin θ and the floor's echo h / sin|θ|; the simulated sonar's
// longer echo over a drop and the fall it counts; the navigator that never drives into
// one (it gives up naming it, or goes around), guiding slowly and telling it; and the world
// file's "drops" with errors naming the field.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "navigation/navigator.h"
#include "navigation/sonar_sweep.h"
#include "sim/sim_runner.h"

using marvin::devices::ScanPoint;
using marvin::navigation::Ahead;
using marvin::navigation::classify_echo;
using marvin::navigation::classify_sweep;
using marvin::navigation::Echo;
using marvin::navigation::GoingPlaces;
using marvin::navigation::GoResult;
using marvin::navigation::Navigator;

namespace {

constexpr double kH = 0.25;  // the sonar above the floor

double rad(double deg) { return deg * marvin::navigation::kPi / 180; }

// A sweep -45..60 by 15 in front of: a vertical surface `x` ahead `height` high (above the
// floor; 0: none) and the floor `drop_m` lower from `drop_at` on.
std::vector<ScanPoint> sweep(double x, double height, double drop_at = 99, double drop_m = 0) {
  std::vector<ScanPoint> out;
  for (int a = -45; a <= 60; a += 15) {
    const double t = rad(a);
    double d = 2.5;
    if (a < 0) {
      const double floor_x = kH / std::tan(-t);
      d = floor_x < drop_at ? kH / std::sin(-t) : (kH + drop_m) / std::sin(-t);
    }
    // The surface: hit where the ray crosses x, if it is below its top and above the floor.
    const double y = kH + x * std::tan(t);
    if (height > 0 && y <= height && y >= 0 && x / std::cos(t) < d) d = x / std::cos(t);
    out.push_back({static_cast<double>(a), std::min(d, 2.5), 0});
  }
  return out;
}

}  // namespace

TEST_CASE("one downward echo: the floor, something on it, a step down; no echo is not a step") {
  CHECK(classify_echo(-30, 0.5, kH).kind == Echo::Kind::kFloor);
  CHECK(classify_echo(-30, 0.3, kH).kind == Echo::Kind::kSomething);
  const Echo drop = classify_echo(-30, 0.84, kH);  // the floor 17 cm lower
  CHECK(drop.kind == Echo::Kind::kStepDown);
  CHECK(drop.ahead_m == doctest::Approx(0.433).epsilon(0.01));
  CHECK(classify_echo(-30, 2.5, kH).kind == Echo::Kind::kNone);
  const Echo up = classify_echo(30, 1.0, kH);
  CHECK(up.kind == Echo::Kind::kSomething);
  CHECK(up.ahead_m == doctest::Approx(0.866).epsilon(0.001));
  CHECK(up.height_m == doctest::Approx(0.5).epsilon(0.001));  // D sin θ, not D tan θ
}

TEST_CASE("a sweep is told: wall, low obstacle, step down, clear") {
  const Ahead wall = classify_sweep(sweep(1.0, 2.5), kH, 1.5);
  CHECK(wall.kind == Ahead::Kind::kWall);
  CHECK(wall.distance_m == doctest::Approx(1.0).epsilon(0.01));
  // A box 15 cm high, lower than the sonar: only the downward beams see it.
  const Ahead low = classify_sweep(sweep(0.6, 0.15), kH, 1.5);
  CHECK(low.kind == Ahead::Kind::kLow);
  CHECK(low.distance_m == doctest::Approx(0.6).epsilon(0.02));
  const Ahead step = classify_sweep(sweep(2.2, 2.5, 0.6, 0.17), kH, 1.5);
  CHECK(step.kind == Ahead::Kind::kStepDown);
  CHECK(step.distance_m == doctest::Approx(0.933).epsilon(0.01));
  const Ahead clear = classify_sweep(sweep(9, 0), kH, 1.5);
  CHECK(clear.kind == Ahead::Kind::kClear);
  CHECK(std::string(marvin::navigation::to_words(Ahead::Kind::kStepDown)) == "a step down");
}

namespace {

// Hall [0,4]x[0,3] and garden [4,9]x[0,3] joined by a door at x = 4; in the garden a step
// down 0.2 m deep across its whole width from x = 4.6 to 5.6. The robot in the hall facing
// east.
const char* kGardenWorld = R"({"format": "marvin-world", "version": 1,
  "rooms": [{"name": "hall", "outline": [[0,0],[4,0],[4,3],[0,3]]},
            {"name": "garden", "outline": [[4,0],[9,0],[9,3],[4,3]], "spot": [7.5, 1.5]}],
  "doors": [{"name": "garden door", "at": [4, 1.5], "width_m": 0.9, "rooms": ["hall", "garden"]}],
  "places": [{"name": "the gate", "at": [4.3, 2.6], "room": "garden"}],
  DROPS
  "robot": {"start": [1, 1.5], "heading_deg": 0}})";

marvin::sim::World garden(const std::string& drops) {
  std::string text = kGardenWorld;
  text.replace(text.find("DROPS"), 5, drops);
  return marvin::sim::parse_world(text, "/tmp/garden.json");
}

const std::string kStep =
    R"("drops": [{"name": "the garden step", "min": [4.6, 0], "max": [5.6, 3], "depth_m": 0.2}],)";

marvin::sim::SimOptions quiet() {
  marvin::sim::SimOptions o;
  o.sonar_dropout = 0;
  return o;
}

// The navigator on the simulated robot stepped by hand, sweeping down as `marvin run --sim`
// does (app/sim_home.cpp).
struct StepRig {
  explicit StepRig(marvin::sim::World world, marvin::sim::SimOptions options = {})
      : runner(std::move(world), options, 1.0),
        nav(
            runner.floor_map(), runner, [this] { return runner.odometry(); },
            [this] { return runner.sim_scan(); }, [this] { return runner.now_ms(); }) {
    runner.set_sweep(1, -30, 60, 15);
  }
  bool wait(std::chrono::milliseconds ms) {
    const bool cancelled = runner.wait(ms, [] { return false; });
    runner.inspect([&](const marvin::sim::Simulator& s) {
      fastest = std::max(fastest, std::max(std::fabs(s.left_m_s()), std::fabs(s.right_m_s())));
      falls = s.falls();
      collisions = s.collisions();
    });
    return cancelled;
  }
  marvin::sim::SimRunner runner;
  Navigator nav;
  double fastest = 0;
  long falls = 0, collisions = 0;
};

}  // namespace

TEST_CASE("the simulated sonar: a longer echo looking down into a drop; driving in is a fall") {
  marvin::sim::World w = garden(kStep);
  marvin::sim::SimOptions exact = quiet();
  exact.sonar_noise_m = 0;
  marvin::sim::Simulator sim(w, exact);
  marvin::navigation::Pose at{4.0, 1.5, 0};  // the floor point of -15° (0.93 m) is in the drop
  CHECK(sim.sonar_geometry_m(at, -30) == doctest::Approx(0.5).epsilon(0.001));
  // Down to the lower floor (0.45 / tan 15° = 1.68 m ahead) it would reach beyond the step's
  // far side (1.6 m ahead): the far side answers.
  CHECK(sim.sonar_geometry_m(at, -15) == doctest::Approx(1.6 / std::cos(rad(15))).epsilon(0.001));
  CHECK(sim.sonar_geometry_m({3.9, 1.5, 0}, -15) ==
        doctest::Approx(0.45 / std::sin(rad(15))).epsilon(0.001));
  CHECK(sim.sonar_geometry_m({3.0, 1.5, 0}, -15) ==
        doctest::Approx(0.25 / std::sin(rad(15))).epsilon(0.001));
  // Straight on over the edge: one fall, the body stays at the edge, motors cut.
  std::string fell;
  sim.on_fall([&](const marvin::navigation::Pose&, const std::string& name) { fell = name; });
  sim.set_motor(0, false, 150);
  sim.set_motor(1, false, 150);
  sim.step(20);
  CHECK(sim.falls() == 1);
  CHECK(fell == "the garden step");
  CHECK(sim.pose().x < 4.6);
  CHECK(sim.left_m_s() == 0);
}

TEST_CASE("the navigator never drives into a step down: across the whole room it gives up") {
  StepRig rig(garden(kStep));
  const GoResult r = rig.nav.go_to("garden", [&](auto ms) { return rig.wait(ms); });
  CHECK(r.outcome == GoResult::Outcome::kGaveUp);
  CHECK(r.reason == "there is a step down on the way to the garden");
  CHECK(rig.falls == 0);
  CHECK(rig.collisions == 0);
  CHECK(rig.runner.true_pose().x < 4.6);
}

TEST_CASE("guiding: slower than going, tells the step down, still arrives where it can") {
  // Without a step the same trip, guided at half speed: slower wheels, "start" and no
  // step down told, arrives.
  StepRig plain(garden(""), quiet());
  std::vector<GoingPlaces::GuideEvent> told;
  GoingPlaces::GuideFn tell = [&](const GoingPlaces::GuideEvent& e) {
    told.push_back(e);
    return true;
  };
  GoResult r = plain.nav.guide_to("garden", 0.5, tell, [&](auto ms) { return plain.wait(ms); });
  CHECK(r.arrived());
  REQUIRE(!told.empty());
  CHECK(told.front().event == "start");
  CHECK(told.front().distance_left_m == doctest::Approx(6.5).epsilon(0.05));
  CHECK(plain.fastest <= 0.5 * 150 / 255.0 * 0.4 + 0.01);
  CHECK(std::none_of(told.begin(), told.end(), [](auto& e) { return e.event == "step_down"; }));

  // With the step: it is told, with its distance, and the robot stops before it.
  StepRig rig(garden(kStep), quiet());
  told.clear();
  r = rig.nav.guide_to("garden", 0.5, tell, [&](auto ms) { return rig.wait(ms); });
  CHECK(r.outcome == GoResult::Outcome::kGaveUp);
  auto step =
      std::find_if(told.begin(), told.end(), [](auto& e) { return e.event == "step_down"; });
  REQUIRE(step != told.end());
  CHECK(step->distance_m < 1.0);
  CHECK(step->stopped == (step->distance_m < 0.5));
  CHECK(rig.falls == 0);
  // The gate is before the step: guided there, it arrives.
  told.clear();
  r = rig.nav.guide_to("the gate", 0.5, tell, [&](auto ms) { return rig.wait(ms); });
  CHECK(r.arrived());
  CHECK(rig.falls == 0);

  // on_event returning false stops the trip at once.
  StepRig stopped(garden(""), quiet());
  GoingPlaces::GuideFn no = [](const GoingPlaces::GuideEvent&) { return false; };
  r = stopped.nav.guide_to("garden", 0.5, no, [&](auto ms) { return stopped.wait(ms); });
  CHECK(r.outcome == GoResult::Outcome::kCancelled);
  CHECK(stopped.runner.true_pose().x == doctest::Approx(1.0).epsilon(0.01));
}

TEST_CASE("world file: a step down's errors name the element and the field") {
  auto error_of = [](const std::string& drops) {
    try {
      garden(drops);
    } catch (const marvin::sim::WorldError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error_of(R"("drops": [{"name": "s", "min": [5, 0], "max": [4.6, 3]}],)") ==
        "/tmp/garden.json: drops[0] \"s\": 'min' [5, 0] must be below and left of 'max' [4.6, 3]");
  CHECK(error_of(R"("drops": [{"name": "s", "min": [4.6, 0], "max": [5, 3], "depth_m": 0}],)")
            .find("drops[0] \"s\": 'depth_m'") != std::string::npos);
  CHECK(error_of(R"("drops": [{"name": "s", "min": [20, 0], "max": [21, 3]}],)") ==
        "/tmp/garden.json: drops[0] \"s\": the step from [20, 0] to [21, 3] is outside every room");
  CHECK(error_of(R"("drops": [{"name": "s", "min": [0.5, 1], "max": [1.5, 2]}],)") ==
        "/tmp/garden.json: robot: 'start' [1, 1.5] is on the step down s");
  CHECK(garden(kStep).drops.at(0).depth_m == doctest::Approx(0.2));
}
