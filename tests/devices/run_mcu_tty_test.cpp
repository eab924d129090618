// Integration: `marvin run --sim --mcu-tty PATH` drives marvin-mcu-sim through a real
// pseudo-terminal. A Lua skill made by the test moves the base; the simulator's state file
// must show the body travelled and the status light the host set. Real processes, real
// tty bytes; every wait is on a condition with a generous timeout.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <poll.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "protocol/marvin_protocol.h"

extern char** environ;

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

nlohmann::json read_state(const fs::path& p) {
  std::ifstream in(p);
  if (!in) return {};
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return {};  // caught mid-write: read again
  }
}

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

pid_t spawn_simulator(const fs::path& link, const fs::path& state) {
  std::vector<std::string> args = {MARVIN_MCU_SIM, "--room",  MARVIN_ROOM,   "--link",
                                   link.string(),  "--state", state.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(rc == 0);
  return pid;
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

  pid_t sim = spawn_simulator(link, state);
  REQUIRE(eventually(dir, [&] { return read_state(state).contains("x"); }));
  const double start_x = read_state(state).value("x", 0.0);

  std::ofstream(dir / "input.txt") << "drive forward\n";
  const std::string command = "MARVIN_SKILLS_DIR='" + (dir / "none").string() + "' '" +
                              MARVIN_EXE + "' run --sim --in-memory --no-builtin-skills " +
                              "--skills-dir '" + (dir / "skills").string() + "' --mcu-tty '" +
                              link.string() + "' < '" + (dir / "input.txt").string() +
                              "' 2> '" + (dir / "stderr.txt").string() + "'";
  FILE* pipe = ::popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string output;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = ::pclose(pipe);
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

  ::kill(sim, SIGTERM);
  int sim_status = 0;
  ::waitpid(sim, &sim_status, 0);
  fs::remove_all(dir);
}
