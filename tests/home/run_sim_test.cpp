// End to end: `marvin run --sim` with a real mosquitto and marvin-home-sim, typed requests
// on stdin, the simulator's devices and Marvin's own topics on the bus checked.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/stat.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "home_fixture.h"
#include "support/files.h"

namespace marvin::home::testing {
namespace {

ChildProcess run_marvin(std::vector<std::string> extra) {
  std::vector<std::string> argv{
      MARVIN_EXE, "run", "--sim", "--no-builtin-skills", "--skills-dir", MARVIN_HOME_SKILL_DIR};
  if (std::find(extra.begin(), extra.end(), "--data-dir") == extra.end())
    argv.push_back("--in-memory");
  argv.insert(argv.end(), extra.begin(), extra.end());
  test_support::ChildOptions o;
  o.err = test_support::ChildStream::kNull;
  ChildProcess marvin(argv, o);
  marvin.wait_for_line_containing("[home: 9 devices on");
  return marvin;
}

TEST_CASE("marvin run --sim: \"turn on the kitchen light\" turns on the simulator's light") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  ChildProcess marvin = run_marvin({"--mqtt", broker.address()});
  marvin.send_line("turn on the kitchen light");
  marvin.wait_for_line("Marvin: The kitchen light is on.");
  sim.wait_for_line("kitchen light: ON 254");
  marvin.send_line("dim the living room lights to 30 percent");
  marvin.wait_for_line("Marvin: The living room lamp is on, at 30 percent.");
  sim.wait_for_line("living room lamp: ON 76");
  marvin.send_line("is the kitchen light on?");
  marvin.wait_for_line("Marvin: Yes, the kitchen light is on.");
  // The heating: the simulator's thermostat reports the new set point before Marvin says it.
  marvin.send_line("make it warmer in the living room");
  marvin.wait_for_line(
      "Marvin: The living room thermostat is on, set to 21 degrees. It's 19.5 degrees in the "
      "living room.");
  sim.wait_for_line("living room thermostat: heat 21");
  CHECK(test_support::exit_code(marvin.finish()) == 0);
}

TEST_CASE("marvin run --sim: 'the light' is the one in the robot's room; Marvin on the bus") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  test_support::TempDir dir;
  test_support::write_text(dir / "home.json",
                           R"({"broker": {"host": "127.0.0.1", "port": )" +
                               std::to_string(broker.port()) +
                               R"(}, "site": "e2e", "room": "study", "commands": true})");
  Peer peer(broker);
  peer.subscribe("marvin/e2e/#");
  peer.subscribe("homeassistant/sensor/marvin_e2e/+/config");
  REQUIRE(peer.wait_connected());
  ChildProcess marvin = run_marvin({"--home-config", (dir / "home.json").string()});
  // The simulated robot starts in the hall: the navigator's room wins over the config's
  // "study" (which only stands in on a robot without a map), so "the light" is the hall's.
  // The ambiguity question itself, for a room without a light, is in the skill's tests
  // (skills-builtin/home/home_skill_test.cpp).
  marvin.send_line("turn on the light");
  marvin.wait_for_line("Marvin: The hall light is on.");
  sim.wait_for_line("hall light: ON");

  // Marvin on the bus: availability, status with the room, Home Assistant discovery.
  CHECK(peer.wait_message("marvin/e2e/availability", "online"));
  CHECK(peer.wait_message("marvin/e2e/status", R"("room":"hall")"));
  std::optional<std::string> sensor =
      peer.wait_message("homeassistant/sensor/marvin_e2e/activity/config");
  REQUIRE(sensor);
  nlohmann::json config = nlohmann::json::parse(*sensor);
  CHECK(config["state_topic"] == "marvin/e2e/status");
  CHECK(config["availability_topic"] == "marvin/e2e/availability");
  // Commands are enabled in this config: "say" on its documented topic.
  REQUIRE(peer.publish("marvin/e2e/command/say", "Dinner is ready."));
  marvin.wait_for_line("Marvin: Dinner is ready.");
  // A crash: the broker publishes the last will.
  marvin.stop(SIGKILL);
  CHECK(peer.wait_message("marvin/e2e/availability", "offline"));
}

TEST_CASE("marvin run --sim: a device that never answers; the broker going away and back") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker, {"--mute", "bedroom fan"});
  test_support::TempDir dir;
  test_support::write_text(dir / "home.json", R"({"broker": {"host": "127.0.0.1", "port": )" +
                                                  std::to_string(broker.port()) +
                                                  R"(}, "answer_timeout_ms": 300})");
  Peer peer(broker);
  peer.subscribe("marvin/home/availability");
  REQUIRE(peer.wait_connected());
  ChildProcess marvin = run_marvin({"--home-config", (dir / "home.json").string()});
  REQUIRE(peer.wait_messages("marvin/home/availability", "online", 1));
  marvin.send_line("switch on the fan");
  marvin.wait_for_line("Marvin: The bedroom fan didn't answer.");

  broker.kill();
  sim.wait_for_line_containing("broker lost");
  marvin.send_line("turn on the kitchen light");
  marvin.wait_for_line(
      "Marvin: I can't reach the home's hub right now, so the kitchen light is unchanged. "
      "I'll keep trying to reconnect.");
  broker.restart();
  sim.wait_for_line("ready again");
  // Marvin reconnects in the background (its birth message says when); the same request
  // works again.
  REQUIRE(peer.wait_messages("marvin/home/availability", "online", 2));
  marvin.send_line("turn on the kitchen light");
  marvin.wait_for_line("Marvin: The kitchen light is on.");
  sim.wait_for_line("kitchen light: ON 254");
  CHECK(test_support::exit_code(marvin.finish()) == 0);
  // The light was switched on once: the request made while the broker was away was not
  // carried out later.
  int actions = 0;
  for (const std::string& line : sim.output_lines()) {
    if (line.rfind("kitchen light:", 0) == 0) ++actions;
  }
  CHECK(actions == 1);
}

TEST_CASE("marvin run --sim without a broker: says the hub is unreachable, keeps running") {
  const int port = test_support::free_tcp_port();  // nobody listens there
  std::vector<std::string> argv{MARVIN_EXE,
                                "run",
                                "--sim",
                                "--in-memory",
                                "--no-builtin-skills",
                                "--skills-dir",
                                MARVIN_HOME_SKILL_DIR,
                                "--mqtt",
                                "127.0.0.1:" + std::to_string(port)};
  test_support::ChildOptions o;
  o.err = test_support::ChildStream::kNull;
  ChildProcess marvin(argv, o);
  marvin.wait_for_line_containing("not reachable after 3 s; still trying]");
  marvin.send_line("turn on the kitchen light");
  marvin.wait_for_line("Marvin: I can't reach the home's hub right now. I'll keep trying.");
  CHECK(test_support::exit_code(marvin.finish()) == 0);
}

TEST_CASE("marvin devices list shows discovered devices with rooms, state and aliases") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  test_support::TempDir data;
  ChildProcess add({MARVIN_EXE, "devices", "alias", "add", "The Big Lamp", "living room lamp",
                    "--data-dir", data.path().string()});
  CHECK(test_support::exit_code(add.finish()) == 0);
  CHECK(add.output() == "\"the big lamp\" now means living room lamp\n");
  ChildProcess bad(
      {MARVIN_EXE, "devices", "alias", "add", "", "tv", "--data-dir", data.path().string()});
  CHECK(test_support::exit_code(bad.finish()) == 2);
  CHECK(bad.errors() == "marvin: alias: a device alias must not be empty\n");

  ChildProcess list({MARVIN_EXE, "devices", "list", "--mqtt", broker.address(), "--data-dir",
                     data.path().string()});
  CHECK(test_support::exit_code(list.finish()) == 0);
  const std::vector<std::string> lines = list.output_lines();
  CHECK(lines.size() == 9);
  CHECK(std::find(lines.begin(), lines.end(),
                  "living room lamp (light, dimmable) in living room: off "
                  "[z2m:living room/living room lamp] aliases: \"the big lamp\"") != lines.end());
  CHECK(std::find(lines.begin(), lines.end(),
                  "bedroom fan (fan) in bedroom: off [z2m:bedroom/bedroom fan]") != lines.end());
  CHECK(std::find(lines.begin(), lines.end(),
                  "bedroom thermostat (thermostat) in bedroom: on, set to 20 °C, measures 18 °C "
                  "[z2m:bedroom/bedroom thermostat]") != lines.end());

  // The alias works by voice too.
  ChildProcess marvin =
      run_marvin({"--mqtt", broker.address(), "--data-dir", data.path().string()});
  marvin.send_line("turn on the big lamp");
  marvin.wait_for_line("Marvin: The living room lamp is on.");
  sim.wait_for_line("living room lamp: ON 254");
}

TEST_CASE("a password file other users can read is refused before anything starts") {
  test_support::TempDir dir;
  test_support::write_text(dir / "pw", "secret\n");
  ::chmod((dir / "pw").c_str(), 0644);
  test_support::write_text(dir / "home.json",
                           R"({"broker": {"user": "marvin", "password_file": "pw"}})");
  std::vector<std::string> argv{MARVIN_EXE,    "run",           "--sim",
                                "--in-memory", "--home-config", (dir / "home.json").string()};
  ChildProcess marvin(argv);
  int status = marvin.finish();
  CHECK(test_support::exit_code(status) == 2);
  CHECK(marvin.errors().find("has mode 0644: other users may read it") != std::string::npos);
}

}  // namespace
}  // namespace marvin::home::testing
