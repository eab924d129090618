// How well the serial base's dead reckoning survives a stall. `marvin run --sim --mcu-tty
// --world` drives marvin-mcu-sim to the front door (a half turn, then 1 m ahead); on the way
// the host, or the simulator, is suspended (SIGSTOP) for a time measured on the simulator's
// clock. Printed: where the body stopped (the simulator's truth) and how far that is from
// where the same trip without a stall stopped, in the same run. Not a test: nothing fails.
//
//   bench_serial_stall            MARVIN_EXE / MARVIN_MCU_SIM override the programs (e.g. to
//                                 measure another build against this one)
#include <signal.h>
#include <stdlib.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "devices/mcu_state.h"
#include "support/child_process.h"
#include "support/files.h"

namespace fs = std::filesystem;
using marvin::devices::test::read_state;
using marvin::devices::test::turned_deg;
using marvin::devices::test::wheel_speeds;
using marvin::test_support::ChildOptions;
using marvin::test_support::ChildProcess;
using marvin::test_support::ChildStream;
using marvin::test_support::TempDir;
using nlohmann::json;

namespace {

std::string program(const char* variable, const char* built) {
  const char* v = std::getenv(variable);
  return v && *v ? v : built;
}

// Polls the simulator's state file (written every 100 ms) until `pred` holds; false after
// `limit`. A benchmark may poll; the tests wait on file events.
bool until(const fs::path& state, const std::function<bool(const json&)>& pred,
           std::chrono::seconds limit = std::chrono::seconds(60)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    const json s = read_state(state);
    if (!s.is_null() && pred(s)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

enum class Who { kNobody, kHost, kSimulator };
// Mid-turn: 45 degrees into the half turn; turn's end: 150 degrees into it, where the sonar's
// readings from the turn were once taken for what lies ahead; mid-leg: 0.3 m along the leg.
enum class When { kMidTurn, kTurnEnd, kMidLeg };

struct Trip {
  double x = 0, y = 0, stalled_ms = 0;
  std::string answer;
};

Trip go_to_front_door(Who who, When when, int stall_ms) {
  const TempDir temp;
  const fs::path dir = temp.path(), link = dir / "tty", state = dir / "state.json";
  fs::create_directories(dir / "skills");
  ChildOptions quiet;
  quiet.out = ChildStream::kNull;
  quiet.err = ChildStream::kNull;
  ChildProcess sim({program("MARVIN_MCU_SIM", MARVIN_MCU_SIM), "--world", MARVIN_WORLD, "--link",
                    link.string(), "--state", state.string()},
                   quiet);
  until(state, [](const json& s) { return s.contains("x"); });
  const json start = read_state(state);
  ChildOptions host_options;
  host_options.environment = {"MARVIN_SKILLS_DIR=" + (dir / "none").string()};
  ChildProcess host(
      {program("MARVIN_EXE", MARVIN_EXE), "run", "--sim", "--in-memory", "--skills-dir",
       (dir / "skills").string(), "--mcu-tty", link.string(), "--world", MARVIN_WORLD},
      host_options);
  host.wait_for_line_containing("[base: connected on");
  host.send_line("go to the front door");
  Trip trip;
  if (who != Who::kNobody) {
    const double heading0 = start.value("heading_deg", 0.0), y0 = start.value("y", 0.0);
    until(state, [&](const json& s) {
      const double turned = turned_deg(s, heading0);
      if (when == When::kMidTurn) return wheel_speeds(s) > 0 && std::abs(turned) >= 45;
      if (when == When::kTurnEnd) return wheel_speeds(s) > 0 && std::abs(turned) >= 150;
      return s.value("left", 0) > 0 && s.value("right", 0) > 0 && y0 - s.value("y", 0.0) >= 0.3;
    });
    const pid_t pid = who == Who::kHost ? host.pid() : sim.pid();
    const int from = read_state(state).value("time_ms", 0);
    ::kill(pid, SIGSTOP);
    if (who == Who::kHost) {
      until(state, [&](const json& s) { return s.value("time_ms", 0) - from >= stall_ms; });
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(stall_ms));  // its clock is stopped
    }
    ::kill(pid, SIGCONT);
    until(state, [&](const json& s) { return s.value("time_ms", 0) > from; });
    trip.stalled_ms = read_state(state).value("time_ms", 0) - from;
  }
  trip.answer = host.wait_for_line("the answer", [](const std::string& line) {
    return line.rfind("Marvin: I'm at", 0) == 0 || line.rfind("Marvin: Sorry", 0) == 0;
  });
  host.finish();
  until(state, [](const json& s) { return wheel_speeds(s) == 0; });
  const json end = read_state(state);
  trip.x = end.value("x", 0.0);
  trip.y = end.value("y", 0.0);
  sim.stop(SIGTERM);
  return trip;
}

}  // namespace

int main() {
  const Trip base = go_to_front_door(Who::kNobody, When::kMidTurn, 0);
  std::printf("no stall: the body stops at (%.3f, %.3f); %s\n\n", base.x, base.y,
              base.answer.c_str());
  std::printf("%-10s %-9s %9s %17s %10s  %s\n", "suspended", "when", "stall ms", "stopped at",
              "off by m", "answer");
  struct Case {
    Who who;
    When when;
    int ms;
  };
  const Case cases[] = {
      {Who::kHost, When::kMidTurn, 600},      {Who::kHost, When::kMidTurn, 2000},
      {Who::kHost, When::kMidLeg, 600},       {Who::kHost, When::kMidLeg, 2000},
      {Who::kHost, When::kTurnEnd, 600},      {Who::kSimulator, When::kMidTurn, 600},
      {Who::kSimulator, When::kTurnEnd, 600}, {Who::kSimulator, When::kMidLeg, 600}};
  for (const Case& c : cases) {
    const Trip t = go_to_front_door(c.who, c.when, c.ms);
    std::printf("%-10s %-9s %9.0f   (%6.3f, %6.3f) %10.3f  %s\n",
                c.who == Who::kHost ? "host" : "simulator",
                c.when == When::kMidTurn  ? "mid-turn"
                : c.when == When::kTurnEnd ? "turn-end"
                                           : "mid-leg",
                t.stalled_ms, t.x, t.y,
                std::hypot(t.x - base.x, t.y - base.y), t.answer.c_str());
  }
  return 0;
}
