// Integration: `marvin run --sim --mcu-tty PATH` drives marvin-mcu-sim through a real
// pseudo-terminal. A Lua skill made by the test moves the base; the simulator's state file
// must show the body travelled and the status light the host set. Real processes, real
// tty bytes; every wait is on a condition with a generous timeout.
#include <doctest/doctest.h>
#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "mcu_simulator.h"
#include "protocol/marvin_protocol.h"

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using marvin::devices::test::read_state;
using marvin::devices::test::start_mcu_simulator;
using marvin::devices::test::turned_deg;
using marvin::devices::test::wheel_speeds;
using marvin::test_support::ChildProcess;
using marvin::test_support::exit_code;

namespace {

// Waits until `pred` (about a file another process rewrites) holds: re-checks on every file
// event in `dir` (inotify), never by sleeping; false after `timeout`.
template <class Pred>
bool eventually(const fs::path& dir, Pred pred, std::chrono::seconds timeout = 60s) {
  const int fd = ::inotify_init1(IN_CLOEXEC);
  REQUIRE(fd >= 0);
  REQUIRE(::inotify_add_watch(fd, dir.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE) >= 0);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  bool held = pred();
  while (!held) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) > 0) {
      char events[4096];
      (void)::read(fd, events, sizeof events);  // drain; the content is not needed
    }
    held = pred();
  }
  ::close(fd);
  return held;
}

void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

}  // namespace

TEST_CASE("run --sim --mcu-tty: a skill's move drives the simulated base over the tty") {
  char tmpl[] = "/tmp/marvin-run-mcu-tty-XXXXXX";
  REQUIRE(::mkdtemp(tmpl) != nullptr);
  const fs::path dir = tmpl;
  const fs::path link = dir / "tty", state = dir / "state.json";

  write_file(dir / "skills" / "drive" / "skill.json", R"({
    "id": "drive", "name": "Drive", "version": "1.0.0", "kind": "lua",
    "host_api": {"min": "1.0"}, "permissions": ["motion", "light"],
    "intents": [{"name": "drive", "templates": ["drive forward"]}]
  })");
  write_file(dir / "skills" / "drive" / "main.lua", R"(
    marvin.on("drive", function()
      marvin.move("forward", 1, 150)
      marvin.say("I drove forward.")
    end)
  )");

  ChildProcess sim = start_mcu_simulator(link, state);
  REQUIRE(eventually(dir, [&] { return read_state(state).contains("x"); }));
  const double start_x = read_state(state).value("x", 0.0);

  marvin::test_support::ChildOptions host_options;
  host_options.environment = {"MARVIN_SKILLS_DIR=" + (dir / "none").string()};
  ChildProcess host({MARVIN_EXE, "run", "--sim", "--in-memory", "--no-builtin-skills",
                     "--skills-dir", (dir / "skills").string(), "--mcu-tty", link.string()},
                    host_options);
  host.write("drive forward\n");
  const int status = host.finish();
  const std::string output = host.output();
  INFO("output:\n" << output);

  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(output.find("[base: connected on " + link.string() + "]") != std::string::npos);
  CHECK(output.find("[move forward, speed 150, 1000 ms]") != std::string::npos);
  CHECK(output.find("Marvin: I drove forward.") != std::string::npos);

  // The move went over the wire: the simulated body travelled, and the last light the host
  // set (awaiting, red) is what the MCU shows.
  CHECK(eventually(dir, [&] { return read_state(state).value("x", 0.0) > start_x + 0.05; }));
  CHECK(eventually(dir, [&] { return read_state(state).value("leds", -1) == MV_LED_RED; }));
  INFO("simulator state: " << read_state(state).dump());
  CHECK(read_state(state).value("collisions", -1) == 0);

  sim.stop(SIGTERM);
  fs::remove_all(dir);
}

TEST_CASE("run --sim --mcu-tty --world: going places over the real serial path, through a stall") {
  // marvin-mcu-sim runs the firmware core in the default home; the host plans on the same
  // world's floor plan and drives by dead reckoning through the tty.
  char tmpl[] = "/tmp/marvin-run-mcu-world-XXXXXX";
  REQUIRE(::mkdtemp(tmpl) != nullptr);
  const fs::path dir = tmpl;
  const fs::path link = dir / "tty", state = dir / "state.json";
  const char* source = std::getenv("MARVIN_SOURCE_DIR");
  REQUIRE(source != nullptr);
  const std::string world = (fs::path(source) / "examples" / "worlds" / "home.json").string();
  marvin::test_support::ChildOptions sim_options;
  sim_options.out = marvin::test_support::ChildStream::kNull;
  sim_options.err = marvin::test_support::ChildStream::kInherit;
  ChildProcess sim({MARVIN_MCU_SIM, "--world", world, "--link", link.string(), "--state",
                    state.string()},
                   sim_options);
  REQUIRE(eventually(dir, [&] { return read_state(state).contains("x"); }));

  fs::create_directories(dir / "skills");
  marvin::test_support::ChildOptions host_options;
  host_options.environment = {"MARVIN_SKILLS_DIR=" + (dir / "none").string()};
  ChildProcess host({MARVIN_EXE, "run", "--sim", "--in-memory", "--skills-dir",
                     (dir / "skills").string(), "--mcu-tty", link.string(), "--world", world},
                    host_options);
  host.wait_for_line_containing("[base: connected on");
  const double start_heading = read_state(state).value("heading_deg", 0.0);
  host.send_line("go to the front door");

  // On the way the host stalls (a busy machine; here SIGSTOP) until the MCU's deadman has
  // stopped the wheels and the link has been quiet for longer than the host's watchdog
  // (1.5 s), both on the simulator's clock. The reckoning must follow the body, which
  // stopped, not the move that was asked for; and the link must be kept.
  // Mid-turn (the trip starts with a half turn), where an error in the reckoning costs most.
  REQUIRE(eventually(dir, [&] {
    const auto s = read_state(state);
    return wheel_speeds(s) > 0 && std::abs(turned_deg(s, start_heading)) >= 45;
  }));
  REQUIRE(::kill(host.pid(), SIGSTOP) == 0);
  const int stalled_at = read_state(state).value("time_ms", 0);
  const bool stopped_by_deadman = eventually(dir, [&] {
    const auto s = read_state(state);
    return wheel_speeds(s) == 0 && s.value("time_ms", 0) - stalled_at >= 2000;
  });
  REQUIRE(::kill(host.pid(), SIGCONT) == 0);
  CHECK(stopped_by_deadman);

  host.wait_for_line("Marvin: I'm at the front door, in the hall.");
  host.send_line("where are you");
  host.wait_for_line("Marvin: I'm in the hall.");
  CHECK(exit_code(host.finish()) == 0);
  INFO("host output:\n" << host.output() << host.errors());
  const std::string lost = "serial link to " + link.string() + " lost";  // serial_link.cpp
  CHECK((host.output() + host.errors()).find(lost) == std::string::npos);

  // The simulated body is there for real (the world's truth, not the host's reckoning).
  auto s = read_state(state);
  INFO("simulator state: " << s.dump());
  CHECK(s.value("collisions", -1) == 0);
  CHECK(std::abs(s.value("x", 0.0) - 5.0) < 0.3);
  CHECK(s.value("y", 9.0) < 1.0);
  sim.stop(SIGTERM);
  fs::remove_all(dir);
}
