// The smart-home service against a real mosquitto and the real simulator process.
#include <doctest/doctest.h>
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "home/discovery.h"
#include "home_fixture.h"

namespace marvin::home::testing {
namespace {

const std::vector<std::string> kWorldDevices = {"hall light",
                                                "living room lamp",
                                                "kitchen light",
                                                "bedroom light",
                                                "bedroom fan",
                                                "bathroom light",
                                                "tv",
                                                "living room thermostat",
                                                "bedroom thermostat"};

bool all_world_devices(const std::vector<Device>& devices) {
  for (const std::string& name : kWorldDevices) {
    if (!has_device(devices, name)) return false;
  }
  return true;
}

// Every device of the world present and its state reported once: the simulator publishes
// discovery and state as separate messages, so a device can be known before its state is.
bool all_world_devices_reported(const std::vector<Device>& devices) {
  if (!all_world_devices(devices)) return false;
  for (const Device& d : devices) {
    if (!d.state.on.has_value()) return false;
  }
  return true;
}

// Resident memory in bytes, from /proc/self/statm.
long resident_bytes() {
  std::ifstream in("/proc/self/statm");
  long pages = 0, resident = 0;
  in >> pages >> resident;
  return resident * ::sysconf(_SC_PAGESIZE);
}

TEST_CASE("Zigbee2MQTT devices of the simulator are discovered with their names and rooms") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(all_world_devices, kWait));
  std::vector<Device> devices = home.devices();
  CHECK(devices.size() == kWorldDevices.size());
  for (const Device& d : devices) {
    if (d.name == "living room lamp") {
      CHECK(d.room == "living room");
      CHECK(d.type == DeviceType::kLight);
      CHECK(d.dimmable);
      CHECK(d.id == "z2m:living room/living room lamp");
    }
    if (d.name == "bedroom fan") {
      CHECK(d.room == "bedroom");
      CHECK(d.type == DeviceType::kFan);
      CHECK_FALSE(d.dimmable);
    }
    if (d.name == "tv") CHECK(d.type == DeviceType::kSwitch);
    if (d.name == "hall light") CHECK_FALSE(d.dimmable);
    if (d.name == "bedroom thermostat") {
      CHECK(d.type == DeviceType::kThermostat);
      CHECK(d.protocol.setpoint_property == "occupied_heating_setpoint");
      CHECK(d.protocol.heat_mode == "heat");
      CHECK(d.protocol.min_c == 5.0);
      CHECK(d.protocol.max_c == 30.0);
    }
  }
  // The retained state came with discovery: everything starts off.
  REQUIRE(home.wait_devices(
      [](const std::vector<Device>& ds) {
        for (const Device& d : ds) {
          if (!d.state.on.has_value()) return false;
        }
        return true;
      },
      kWait));
  // The thermostats heat from the start; they report the world's room temperature.
  for (const Device& d : home.devices()) {
    CHECK(d.state.on == (d.type == DeviceType::kThermostat));
    if (d.name == "bedroom thermostat") {
      CHECK(d.state.target_c == 20.0);
      CHECK(d.state.current_c == 18.0);
    }
  }
}

TEST_CASE("a thermostat's set point and its heating off are confirmed from its report") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(all_world_devices, kWait));
  const std::string bedroom = id_of(home, "bedroom thermostat");
  // 21.3 asked: the thermostat keeps half degrees and reports 21.5, which is the command done.
  HomeService::SetResult warmer = home.set(bedroom, DeviceCommand{{}, {}, {}, 21.3});
  CHECK(warmer.outcome == HomeService::Outcome::kConfirmed);
  CHECK(warmer.state.target_c == 21.5);
  CHECK(warmer.state.current_c == 18.0);
  sim.wait_for_line("bedroom thermostat: heat 21.5");
  HomeService::SetResult off = home.set(bedroom, DeviceCommand{false, {}, {}, {}});
  CHECK(off.outcome == HomeService::Outcome::kConfirmed);
  CHECK(off.state.on == false);
  CHECK(off.state.target_c == 21.5);  // off keeps the set point for when it heats again
  sim.wait_for_line("bedroom thermostat: off 21.5");
}

TEST_CASE("on, off, dim and query are confirmed from the device's reported state") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(all_world_devices, kWait));
  const std::string kitchen = id_of(home, "kitchen light");

  HomeService::SetResult on = home.set(kitchen, DeviceCommand{true, {}, {}, {}});
  CHECK(on.outcome == HomeService::Outcome::kConfirmed);
  CHECK(on.state.on == true);
  sim.wait_for_line("kitchen light: ON 254");

  HomeService::SetResult dim = home.set(kitchen, DeviceCommand{{}, 30, {}, {}});
  CHECK(dim.outcome == HomeService::Outcome::kConfirmed);
  CHECK(dim.state.brightness_pct == 30);
  sim.wait_for_line("kitchen light: ON 76");  // 30 % of 254

  // Query: the state the device reported, as kept by the service.
  std::optional<Device> now = home.device(kitchen);
  REQUIRE(now);
  CHECK(now->state.on == true);
  CHECK(now->state.brightness_pct == 30);

  HomeService::SetResult off = home.set(kitchen, DeviceCommand{false, {}, {}, {}});
  CHECK(off.outcome == HomeService::Outcome::kConfirmed);
  CHECK(off.state.on == false);
  sim.wait_for_line("kitchen light: OFF 76");

  CHECK(home.set("z2m:nowhere/nothing", DeviceCommand{true, {}, {}, {}}).outcome ==
        HomeService::Outcome::kUnknownDevice);
}

TEST_CASE("a device that never answers is reported as not answering, not as done") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker, {"--mute", "bedroom fan"});
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(all_world_devices_reported, kWait));
  HomeService::SetResult r = home.set(id_of(home, "bedroom fan"), DeviceCommand{true, {}, {}, {}},
                                      std::chrono::milliseconds(300));
  CHECK(r.outcome == HomeService::Outcome::kNoAnswer);
  CHECK(r.state.on == false);
  CHECK(home.device(id_of(home, "bedroom fan"))->state.on == false);
}

TEST_CASE("Home Assistant discovery: a JSON-schema light and a default-schema switch") {
  MosquittoBroker broker;
  Peer device(broker, "ha-device");
  REQUIRE(device.wait_connected());
  // The "device" side: answers commands by reporting state, as a real one would.
  device.on_message([&](const std::string& t, const std::string& p) {
    if (t == "home/desk/set") {
      nlohmann::json cmd = nlohmann::json::parse(p);
      nlohmann::json state{{"state", cmd.value("state", "ON")}};
      if (cmd.contains("brightness")) state["brightness"] = cmd["brightness"];
      device.publish("home/desk/state", state.dump(), true);
    }
    if (t == "home/heater/cmd")
      device.publish("home/heater/stat", p == "turn_on" ? "is_on" : "is_off", true);
  });
  device.subscribe("home/desk/set");
  device.subscribe("home/heater/cmd");
  device.publish("homeassistant/light/desk/config",
                 R"({"name": "Desk Lamp", "~": "home/desk", "cmd_t": "~/set", "stat_t": "~/state",
                     "schema": "json", "brightness": true, "unique_id": "desk1",
                     "device": {"identifiers": ["desk"], "name": "Desk", "suggested_area": "Study"}})",
                 true);
  device.publish("homeassistant/switch/node7/heater/config",
                 R"({"name": "Heater", "command_topic": "home/heater/cmd",
                     "state_topic": "home/heater/stat", "payload_on": "turn_on",
                     "payload_off": "turn_off", "state_on": "is_on", "state_off": "is_off",
                     "device": {"identifiers": ["h"], "suggested_area": "Bathroom"}})",
                 true);
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(
      [](const std::vector<Device>& ds) {
        return has_device(ds, "desk lamp") && has_device(ds, "heater");
      },
      kWait));
  std::optional<Device> desk = home.device("ha:light/desk");
  REQUIRE(desk);
  CHECK(desk->room == "study");
  CHECK(desk->dimmable);
  std::optional<Device> heater = home.device("ha:switch/node7/heater");
  REQUIRE(heater);
  CHECK(heater->room == "bathroom");
  CHECK(heater->type == DeviceType::kSwitch);

  HomeService::SetResult r = home.set("ha:light/desk", DeviceCommand{true, 50, {}, {}});
  CHECK(r.outcome == HomeService::Outcome::kConfirmed);
  CHECK(r.state.brightness_pct == 50);
  r = home.set("ha:switch/node7/heater", DeviceCommand{true, {}, {}, {}});
  CHECK(r.outcome == HomeService::Outcome::kConfirmed);
  CHECK(r.state.on == true);

  // An empty retained config removes the device.
  device.publish("homeassistant/switch/node7/heater/config", "", true);
  CHECK(home.wait_devices([](const std::vector<Device>& ds) { return !has_device(ds, "heater"); },
                          kWait));
}

TEST_CASE("broker killed and restarted: no crash, commands work again, no duplicate actions") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(all_world_devices, kWait));
  const std::string hall = id_of(home, "hall light");
  REQUIRE(home.set(hall, DeviceCommand{true, {}, {}, {}}).outcome == HomeService::Outcome::kConfirmed);
  sim.wait_for_line("hall light: ON");

  broker.kill();
  REQUIRE(home.wait_devices([&](const std::vector<Device>&) { return !home.connected(); }, kWait));
  // While the broker is away: said so at once, and nothing is queued for later.
  CHECK(home.set(hall, DeviceCommand{false, {}, {}, {}}).outcome ==
        HomeService::Outcome::kBrokerUnreachable);
  sim.wait_for_line_containing("broker lost");

  const int before = home.connections();
  broker.restart();
  REQUIRE(home.wait_connected(kWait));
  CHECK(home.connections() == before + 1);
  sim.wait_for_line("ready again");
  // The simulator re-announced its devices; the hall light is still on (the command sent
  // during the outage was never carried out).
  REQUIRE(home.wait_devices(all_world_devices, kWait));
  REQUIRE(home.set(hall, DeviceCommand{false, {}, {}, {}}).outcome == HomeService::Outcome::kConfirmed);
  sim.wait_for_line("hall light: OFF");
  REQUIRE(home.set(hall, DeviceCommand{true, {}, {}, {}}).outcome == HomeService::Outcome::kConfirmed);
  sim.wait_for_line("hall light: ON");
  // Exactly the three confirmed commands reached the device: ON, OFF, ON.
  int actions = 0;
  for (const std::string& line : sim.output_lines()) {
    if (line.rfind("hall light:", 0) == 0) ++actions;
  }
  CHECK(actions == 3);
}

TEST_CASE("malformed discovery and retained garbage are ignored with a log line naming the topic") {
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  LogCapture log;
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  REQUIRE(home.wait_devices(all_world_devices_reported, kWait));
  Peer peer(broker);
  REQUIRE(peer.wait_connected());
  peer.publish("homeassistant/light/broken/config", "{not json", true);
  CHECK(log.wait_for({"ignored homeassistant/light/broken/config", "not valid JSON at byte"}));
  peer.publish("homeassistant/fan/nocmd/config", R"({"name": "Ceiling fan"})", true);
  CHECK(log.wait_for({"ignored homeassistant/fan/nocmd/config", "\"command_topic\" is missing"}));
  peer.publish("homeassistant/light/badname/config", R"({"name": 7, "command_topic": "x"})", true);
  CHECK(log.wait_for({"ignored homeassistant/light/badname/config", "\"name\" must be a string"}));
  // Retained garbage where the device list and a device's state should be.
  peer.publish("zigbee2mqtt/bridge/devices", "\x01\x02garbage", true);
  CHECK(log.wait_for({"ignored zigbee2mqtt/bridge/devices", "not valid JSON"}));
  peer.publish("zigbee2mqtt/kitchen/kitchen light", "garbage", true);
  CHECK(log.wait_for({"ignored zigbee2mqtt/kitchen/kitchen light", "not a state"}));
  // Nothing that was known is lost or changed.
  std::vector<Device> devices = home.devices();
  CHECK(devices.size() == kWorldDevices.size());
  CHECK(all_world_devices(devices));
  CHECK(home.device(id_of(home, "kitchen light"))->state.on == false);
  // And the service still works.
  CHECK(home.set(id_of(home, "kitchen light"), DeviceCommand{true, {}, {}, {}}).outcome ==
        HomeService::Outcome::kConfirmed);
}

TEST_CASE("1 MB payloads are dropped unread and do not grow memory") {
  MosquittoBroker broker;
  LogCapture log;
  HomeService home(config_for(broker));
  home.start();
  REQUIRE(home.wait_connected(kWait));
  Peer peer(broker);
  REQUIRE(peer.wait_connected());
  const std::string big(1024 * 1024, '{');
  peer.publish("homeassistant/light/big/config", big, true);
  REQUIRE(log.wait_for({"ignored homeassistant/light/big/config", "1048576 bytes"}));
  // Two rounds of 10 MB, one message at a time: the first warms the allocators (of the
  // publisher here and of the receiving client); the second must not add to it, as it
  // would by 10 MB if payloads were kept.
  long before = 0;
  for (int round = 0; round < 2; ++round) {
    if (round == 1) before = resident_bytes();
    for (int i = 0; i < 10; ++i) {
      const std::string t =
          "homeassistant/light/big" + std::to_string(round) + "_" + std::to_string(i) + "/config";
      peer.publish(t, big);
      REQUIRE(log.wait_for({"ignored " + t + ":"}));
    }
  }
  CHECK(home.devices().empty());
#if !defined(__SANITIZE_ADDRESS__)
  // (ASan's quarantine keeps freed blocks, so the figure means nothing there.)
  const long grown = resident_bytes() - before;
  CHECK_MESSAGE(grown < 4L * 1024 * 1024, "resident memory grew by " << grown << " bytes");
#else
  (void)before;
#endif
}

TEST_CASE("commands over the bus: ignored unless enabled, then only the documented topics") {
  MosquittoBroker broker;
  LogCapture log;
  Peer peer(broker);
  peer.subscribe("marvin/test/#");
  REQUIRE(peer.wait_connected());
  std::mutex mutex;
  std::vector<std::string> taken;
  auto record = [&](const std::string& name, const std::string& payload) {
    std::lock_guard lock(mutex);
    taken.push_back(name + ": " + payload);
  };
  {
    HomeService off(config_for(broker));  // commands: false, the default
    off.on_command(record);
    off.start();
    REQUIRE(off.wait_connected(kWait));
    REQUIRE(peer.publish("marvin/test/command/say", "hello"));
    // The broker has routed it to every subscriber once the peer has its own copy; the
    // service's marker (settle) travels behind it.
    REQUIRE(peer.wait_message("marvin/test/command/say", "hello"));
    REQUIRE(off.settle(kWait));
    std::lock_guard lock(mutex);
    CHECK(taken.empty());
  }
  HomeConfig config = config_for(broker);
  config.commands = true;
  HomeService on(config);
  on.on_command(record);
  on.start();
  REQUIRE(on.wait_connected(kWait));
  REQUIRE(peer.publish("marvin/test/command/reboot", "now"));
  REQUIRE(peer.publish("marvin/test/command/utterance", "turn on the fan"));
  REQUIRE(peer.wait_message("marvin/test/command/utterance"));
  REQUIRE(on.settle(kWait));
  CHECK(log.wait_for({"ignored marvin/test/command/reboot", "not a command Marvin takes"}));
  std::lock_guard lock(mutex);
  CHECK(taken == std::vector<std::string>{"utterance: turn on the fan"});
}

TEST_CASE("Marvin's presence: availability, status with the room hook, events, HA discovery") {
  MosquittoBroker broker;
  Peer peer(broker);
  peer.subscribe("marvin/test/#");
  peer.subscribe("homeassistant/+/marvin_test/+/config");
  REQUIRE(peer.wait_connected());
  HomeService home(config_for(broker));
  home.set_room_hook([] { return std::string("Kitchen"); });
  home.start();
  REQUIRE(home.wait_connected(kWait));
  CHECK(peer.wait_message("marvin/test/availability", "online"));
  home.publish_activity("speaking");
  CHECK(peer.wait_message("marvin/test/status", R"({"activity":"speaking","room":"kitchen"})"));
  home.publish_event("intruder_alert", "someone unknown in the hall");
  std::optional<std::string> event = peer.wait_message("marvin/test/event", "intruder_alert");
  REQUIRE(event);
  CHECK(nlohmann::json::parse(*event)["text"] == "someone unknown in the hall");
  std::optional<std::string> discovery =
      peer.wait_message("homeassistant/event/marvin_test/event/config");
  REQUIRE(discovery);
  CHECK(nlohmann::json::parse(*discovery)["event_types"].size() == 4);
  home.stop();  // a clean stop says offline too
  CHECK(peer.wait_message("marvin/test/availability", "offline"));
}

}  // namespace
}  // namespace marvin::home::testing
