// Integration: the host's serial body talks to marvin-mcu-sim over a real pseudo-terminal.
// Real bytes, real tty, real processes; every wait is on a condition with a generous
// timeout, and nothing asserts on time.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "devices/serial_body.h"

extern char** environ;

using namespace marvin::devices;
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

class SimProcess {
 public:
  SimProcess(const fs::path& link, const fs::path& state) {
    std::vector<std::string> args = {MARVIN_MCU_SIM, "--room",  MARVIN_ROOM,   "--link",
                                     link.string(),  "--state", state.string()};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    REQUIRE(rc == 0);
  }
  ~SimProcess() { stop(SIGTERM); }
  void stop(int sig) {
    if (pid_ <= 0) return;
    ::kill(pid_, sig);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

nlohmann::json read_state(const fs::path& p) {
  std::ifstream in(p);
  if (!in) return {};
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return {};
  }
}

}  // namespace

TEST_CASE("serial body drives marvin-mcu-sim to a wall, stops by itself, survives a restart") {
  char tmpl[] = "/tmp/marvin-mcu-sim-test-XXXXXX";
  REQUIRE(::mkdtemp(tmpl) != nullptr);
  fs::path dir = tmpl;
  fs::path link = dir / "tty", state = dir / "state.json";

  auto sim = std::make_unique<SimProcess>(link, state);
  Recorder rec;
  LinkOptions options{link.string(), 50ms, 1500ms};
  SerialBody body(options, SweepSettings{0, 30, 15});
  int cb = body.link().add_telemetry_callback([&](const Telemetry& t) { rec.on(t); });
  int scb = body.link().add_state_callback([&](LinkState, const std::string&) { rec.poke(); });

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
  auto scan = body.latest_scan();
  REQUIRE(!scan.empty());
  CHECK(scan.front().angle_deg == 0);
  CHECK(scan.front().distance_m < 0.4);

  // The simulator dies: the link reports the loss.
  sim->stop(SIGKILL);
  REQUIRE(rec.wait([&] {
    return body.link().state() == LinkState::kDisconnected && body.link().counters().losses >= 1;
  }));
  CHECK_FALSE(body.link().send_locomotion(MV_LEFT_FORWARD, 10));

  // ... and comes back at the same path: the link reconnects and the body works again.
  auto statuses_before = rec.statuses;
  sim = std::make_unique<SimProcess>(link, state);
  REQUIRE(rec.wait(
      [&] { return body.link().counters().connects >= 2 && rec.statuses >= statuses_before + 2; }));
  CHECK(rec.wait([&] { return read_state(state).value("leds", 0) == MV_LED_YELLOW; }));  // resent
  body.tilt_head(20);
  REQUIRE(rec.wait([&] { return rec.status && rec.status->head_deg == 20; }));
  body.move(Direction::kBackward, 100, 400ms);
  REQUIRE(rec.wait(
      [&] { return rec.status && rec.status->left_backward && rec.status->left_speed == 100; }));
  // The drive ends by itself after its duration.
  REQUIRE(rec.wait(
      [&] { return rec.status && rec.status->left_speed == 0 && rec.status->right_speed == 0; }));
  CHECK(read_state(state).value("x", 0.0) < 0.0);

  body.link().remove_callback(cb);
  body.link().remove_callback(scb);
  sim.reset();
  fs::remove_all(dir);
}
