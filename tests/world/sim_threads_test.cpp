// The simulated robot on its own thread (as `marvin run --sim` runs it): the navigator on
// another thread reaches the kitchen on the paced simulation, and a "stop" from a third
// thread ends the trip at once with the wheels stopped. Runs under ThreadSanitizer too.
#include <doctest/doctest.h>

#include <atomic>
#include <thread>

#include "navigation/navigator.h"
#include "sim/sim_runner.h"

using marvin::navigation::GoResult;

namespace {

struct Threaded {
  Threaded()
      : runner(marvin::sim::load_world(marvin::sim::default_world_file()), {}, 50.0),
        nav(
            runner.floor_map(), runner, [this] { return runner.odometry(); },
            [this] { return runner.sim_scan(); }, [this] { return runner.now_ms(); }) {
    runner.start();
  }
  GoResult go(const std::string& where) {
    return nav.go_to(where, [this](std::chrono::milliseconds ms) {
      return runner.wait(ms, [this] { return cancelled.load(); });
    });
  }
  std::atomic<bool> cancelled{false};
  marvin::sim::SimRunner runner;
  marvin::navigation::Navigator nav;
};

}  // namespace

TEST_CASE("threaded: the navigator reaches the kitchen on the running simulation") {
  Threaded t;
  GoResult r;
  std::thread trip([&] { r = t.go("kitchen"); });
  trip.join();
  CHECK(r.arrived());
  CHECK(t.nav.where_am_i() == std::optional<std::string>("kitchen"));
  t.runner.inspect([](const marvin::sim::Simulator& s) { CHECK(s.collisions() == 0); });
}

TEST_CASE("threaded: stop from another thread ends the trip and stops the wheels") {
  Threaded t;
  GoResult r;
  std::thread trip([&] { r = t.go("bedroom"); });
  // Two simulated seconds into the trip, the user says "stop".
  t.runner.wait(std::chrono::milliseconds(2000), [] { return false; });
  t.cancelled.store(true);
  t.runner.poke();
  trip.join();
  CHECK(r.outcome == GoResult::Outcome::kCancelled);
  t.runner.wait(std::chrono::milliseconds(500), [] { return false; });  // decelerated
  t.runner.inspect([](const marvin::sim::Simulator& s) {
    CHECK(s.left_m_s() == 0);
    CHECK(s.right_m_s() == 0);
  });
  CHECK(t.nav.where_am_i() != std::optional<std::string>("bedroom"));
}
