// Integration: the host's serial body talks to marvin-mcu-sim over a real pseudo-terminal.
// Real bytes, real tty, real processes; every wait is on a condition with a generous
// timeout, and nothing asserts on time.
#include <doctest/doctest.h>
#include <signal.h>
#include <stdlib.h>

#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "devices/serial_body.h"
#include "mcu_simulator.h"

using namespace marvin::devices;
using marvin::devices::test::read_state;
using marvin::devices::test::start_mcu_simulator;
using marvin::devices::test::start_mcu_simulator_in_world;
using marvin::test_support::ChildProcess;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// Everything the link reported, for waiting on.
struct Recorder {
  std::mutex mu;
  std::condition_variable cv;
  std::vector<Fault> faults;
  std::optional<Status> status;
  std::uint64_t statuses = 0, readings = 0;

  void on(const Telemetry& t) {
    {
      std::lock_guard lock(mu);
      if (auto* f = std::get_if<Fault>(&t)) faults.push_back(*f);
      if (auto* s = std::get_if<Status>(&t)) {
        status = *s;
        ++statuses;
      }
      if (std::holds_alternative<SonarReading>(t)) ++readings;
    }
    cv.notify_all();
  }
  void poke() { cv.notify_all(); }

  // Waits until pred() (called under the lock) holds; re-checks at least every 50 ms for
  // conditions outside the recorder (the simulator's state file). False on timeout.
  template <class Pred>
  bool wait(Pred pred, std::chrono::seconds timeout = 30s) {
    auto deadline = std::chrono::steady_clock::now() + timeout;
    std::unique_lock lock(mu);
    while (!pred()) {
      if (std::chrono::steady_clock::now() >= deadline) return false;
      cv.wait_for(lock, 50ms);
    }
    return true;
  }
};

}  // namespace

TEST_CASE("serial body drives marvin-mcu-sim to a wall, stops by itself, survives a restart") {
  char tmpl[] = "/tmp/marvin-mcu-sim-test-XXXXXX";
  REQUIRE(::mkdtemp(tmpl) != nullptr);
  fs::path dir = tmpl;
  fs::path link = dir / "tty", state = dir / "state.json";

  auto sim = std::make_unique<ChildProcess>(start_mcu_simulator(link, state));
  Recorder rec;
  LinkOptions options{link.string(), 50ms, 1500ms};
  SerialBody body(options, SweepSettings{0, 30, 15});
  int cb = body.link().add_telemetry_callback([&](const Telemetry& t) { rec.on(t); });
  int scb = body.link().add_state_callback([&](LinkState, const std::string&) { rec.poke(); });
  // What the wheels were told, as dead reckoning hears it (MotorBase's observer).
  std::mutex told_mu;
  std::vector<MotorBase::WheelCommand> told;
  body.motors().set_observer([&](const MotorBase::WheelCommand& c) {
    std::lock_guard lock(told_mu);
    told.push_back(c);
  });
  auto told_so_far = [&] {
    std::lock_guard lock(told_mu);
    return told;
  };
  // One drive as told: its frames (the first and each refresh), in time order, then speed 0
  // (the stop; the MCU may report stopping more than once: refresh frames already on their
  // way when it stopped for an obstacle are refused, each with a fault).
  auto check_drive = [](const std::vector<MotorBase::WheelCommand>& commands, Direction direction,
                        int speed) {
    std::size_t stop = 0;
    while (stop < commands.size() && commands[stop].speed != 0) ++stop;
    CHECK(stop >= 1);
    CHECK(stop < commands.size());
    for (std::size_t i = 0; i < commands.size(); ++i) {
      CAPTURE(i);
      if (i < stop) {
        CHECK(commands[i].direction == direction);
        CHECK(commands[i].speed == speed);
      } else {
        CHECK(commands[i].speed == 0);
      }
      if (i > 0) CHECK(commands[i - 1].at <= commands[i].at);
    }
  };

  // Connected and talking: status telemetry arrives.
  REQUIRE(rec.wait([&] { return rec.statuses >= 2; }));
  CHECK(body.link().state() == LinkState::kConnected);

  // Move forward: the status telemetry shows both wheels forward, the body advances.
  body.set_light(Light::kExecuting);
  body.move(Direction::kForward, 150, 60s);
  REQUIRE(rec.wait([&] {
    return rec.status && rec.status->left_speed == 150 && rec.status->right_speed == 150 &&
           !rec.status->left_backward;
  }));
  REQUIRE(rec.wait([&] { return read_state(state).value("x", 0.0) > 0.2; }));

  // ... until the sonar sees the wall: the MCU stops by itself and reports it.
  REQUIRE(rec.wait(
      [&] {
        for (const Fault& f : rec.faults)
          if (f.code == MV_FAULT_OBSTACLE) return true;
        return false;
      },
      60s));
  REQUIRE(rec.wait(
      [&] { return rec.status && rec.status->left_speed == 0 && rec.status->right_speed == 0; }));
  CHECK(rec.wait([&] {
    auto s = read_state(state);
    return s.value("left", 1) == 0 && s.value("right", 1) == 0;
  }));
  auto s = read_state(state);
  INFO("simulator state: " << s.dump());
  CHECK(s.value("collisions", -1) == 0);
  CHECK(s.value("x", 0.0) > 0.6);             // it really travelled
  CHECK(s.value("clearance_m", 0.0) > 0.15);  // and stopped with the body clear of the wall
  CHECK(s.value("leds", 0) == MV_LED_YELLOW);
  CHECK_FALSE(body.motors().driving());
  // Told: the drive's frames (its first and each refresh), then the MCU's own stop.
  CHECK(rec.wait([&] {
    const auto t = told_so_far();
    return !t.empty() && t.back().speed == 0;
  }));
  check_drive(told_so_far(), Direction::kForward, 150);
  // The scan is the median of each angle's last 5 readings: it shows the wall once enough
  // readings from the stopped body have come in, which on a loaded machine is after the stop.
  std::vector<ScanPoint> scan;
  rec.wait([&] {
    scan = body.latest_scan();
    return !scan.empty() && scan.front().angle_deg == 0 && scan.front().distance_m < 0.4;
  });
  REQUIRE(!scan.empty());
  CHECK(scan.front().angle_deg == 0);
  CHECK(scan.front().distance_m < 0.4);
  // A turn starts the scan afresh: no point read before it is left (sonar_scanner.h).
  // (Milliseconds: a point read in the same millisecond as before_turn is still before it.)
  const std::int64_t before_turn = steady_ms();
  CHECK(scan.front().time_ms <= before_turn);
  body.move(Direction::kLeft, 60, 100ms);
  for (const ScanPoint& p : body.latest_scan()) CHECK(p.time_ms >= before_turn);

  // The simulator dies: the link reports the loss.
  sim->stop(SIGKILL);
  REQUIRE(rec.wait([&] {
    return body.link().state() == LinkState::kDisconnected && body.link().counters().losses >= 1;
  }));
  CHECK_FALSE(body.link().send_locomotion(MV_LEFT_FORWARD, 10));
  // A drive while the link is down reaches no wheel: nothing is told.
  const std::size_t told_while_up = told_so_far().size();
  body.move(Direction::kForward, 90, 1s);
  body.stop();
  CHECK(told_so_far().size() == told_while_up);

  // ... and comes back at the same path: the link reconnects and the body works again.
  auto statuses_before = rec.statuses;
  sim = std::make_unique<ChildProcess>(start_mcu_simulator(link, state));
  REQUIRE(rec.wait(
      [&] { return body.link().counters().connects >= 2 && rec.statuses >= statuses_before + 2; }));
  CHECK(rec.wait([&] { return read_state(state).value("leds", 0) == MV_LED_YELLOW; }));  // resent
  body.tilt_head(20);
  REQUIRE(rec.wait([&] { return rec.status && rec.status->head_deg == 20; }));
  const std::size_t told_before_back = told_so_far().size();
  body.move(Direction::kBackward, 100, 400ms);
  REQUIRE(rec.wait(
      [&] { return rec.status && rec.status->left_backward && rec.status->left_speed == 100; }));
  // The drive ends by itself after its duration.
  REQUIRE(rec.wait(
      [&] { return rec.status && rec.status->left_speed == 0 && rec.status->right_speed == 0; }));
  CHECK(read_state(state).value("x", 0.0) < 0.0);
  // Told: that drive, then STOP_ALL when its duration ended.
  CHECK(rec.wait([&] {
    const auto t = told_so_far();
    return t.size() > told_before_back && t.back().speed == 0;
  }));
  auto back = told_so_far();
  back.erase(back.begin(), back.begin() + static_cast<std::ptrdiff_t>(told_before_back));
  check_drive(back, Direction::kBackward, 100);

  body.motors().set_observer({});
  body.link().remove_callback(cb);
  body.link().remove_callback(scb);
  sim->stop(SIGTERM);
  fs::remove_all(dir);
}

TEST_CASE("marvin-mcu-sim --world: the firmware's obstacle stop against the world's sonar") {
  char tmpl[] = "/tmp/marvin-mcu-sim-world-XXXXXX";
  REQUIRE(::mkdtemp(tmpl) != nullptr);
  fs::path dir = tmpl;
  fs::path link = dir / "tty", state = dir / "state.json", world = dir / "world.json";
  // A 3 m x 2 m room; the robot 1.4 m from the west wall facing the east one, 1.6 m away.
  std::ofstream(world) << R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[3,0],[3,2],[0,2]]}],
    "robot": {"start": [1.4, 1], "heading_deg": 0}})";
  auto sim = std::make_unique<ChildProcess>(start_mcu_simulator_in_world(world, link, state));
  Recorder rec;
  LinkOptions options{link.string(), 50ms, 1500ms};
  SerialBody body(options, SweepSettings{0, 30, 15});
  int cb = body.link().add_telemetry_callback([&](const Telemetry& t) { rec.on(t); });
  REQUIRE(rec.wait([&] { return rec.statuses >= 2; }));
  body.move(Direction::kForward, 200, 60s);
  REQUIRE(rec.wait(
      [&] {
        for (const Fault& f : rec.faults)
          if (f.code == MV_FAULT_OBSTACLE) return true;
        return false;
      },
      60s));
  REQUIRE(rec.wait([&] {
    auto s = read_state(state);
    return s.value("left", 1) == 0 && s.value("right", 1) == 0;
  }));
  auto s = read_state(state);
  INFO("simulator state: " << s.dump());
  CHECK(s.value("collisions", -1) == 0);
  CHECK(s.value("x", 0.0) > 2.2);             // it crossed to the far wall
  CHECK(s.value("clearance_m", 0.0) > 0.15);  // and stopped clear of the wall
  body.link().remove_callback(cb);
  sim->stop(SIGTERM);
  fs::remove_all(dir);
}
