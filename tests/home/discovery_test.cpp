// Discovery payloads and state reports, parsed without a broker.
#include "home/discovery.h"

#include <doctest/doctest.h>

namespace marvin::home {
namespace {

TEST_CASE("discovery topics: light, switch and fan configs, with or without a node id") {
  std::string component, object;
  CHECK(parse_ha_config_topic("homeassistant", "homeassistant/light/desk/config", &component,
                              &object));
  CHECK(component == "light");
  CHECK(object == "desk");
  CHECK(parse_ha_config_topic("homeassistant", "homeassistant/fan/n1/ceiling/config", &component,
                              &object));
  CHECK(object == "n1/ceiling");
  CHECK_FALSE(
      parse_ha_config_topic("homeassistant", "homeassistant/sensor/t/config", &component, &object));
  CHECK_FALSE(parse_ha_config_topic("homeassistant", "homeassistant/light/desk/state", &component,
                                    &object));
  CHECK_FALSE(
      parse_ha_config_topic("homeassistant", "other/light/desk/config", &component, &object));
}

TEST_CASE("a default-schema light: brightness on its own topics, scaled") {
  Device d = parse_ha_config("light", "kitchen", R"({"name": "Kitchen_Ceiling",
      "command_topic": "k/set", "state_topic": "k/state", "brightness_command_topic": "k/b/set",
      "brightness_state_topic": "k/b", "brightness_scale": 100,
      "availability": [{"topic": "k/avail"}]})");
  CHECK(d.name == "kitchen ceiling");
  CHECK(d.dimmable);
  CHECK(d.protocol.availability_topic == "k/avail");
  auto messages = command_messages(d, DeviceCommand{true, 40, {}, {}});
  REQUIRE(messages.size() == 2);
  CHECK(messages[0] == std::pair<std::string, std::string>{"k/set", "ON"});
  CHECK(messages[1] == std::pair<std::string, std::string>{"k/b/set", "40"});
  DeviceState s;
  CHECK(apply_state(d, "k/state", "ON", &s));
  CHECK(apply_state(d, "k/b", "40", &s));
  CHECK(s.on == true);
  CHECK(s.brightness_pct == 40);
  CHECK_FALSE(apply_state(d, "k/b", "forty", &s));
  CHECK(s.brightness_pct == 40);
  CHECK(apply_availability(d, "offline", &s));
  CHECK_FALSE(s.available);
  CHECK_FALSE(apply_availability(d, "maybe", &s));
  CHECK_FALSE(s.available);
}

TEST_CASE("malformed configs say what is wrong") {
  CHECK_THROWS_WITH_AS(parse_ha_config("light", "x", "[1,2]"),
                       "the discovery config must be a JSON object", DiscoveryError);
  CHECK_THROWS_WITH_AS(parse_ha_config("light", "x", R"({"name":"a"})"),
                       "\"command_topic\" is missing", DiscoveryError);
  CHECK_THROWS_WITH_AS(
      parse_ha_config("light", "x", R"({"command_topic":"c","brightness_scale":0})"),
      "\"brightness_scale\" must be a positive integer", DiscoveryError);
  CHECK_THROWS_WITH_AS(parse_z2m_devices("z", R"({"a":1})"), "the device list must be a JSON array",
                       DiscoveryError);
  CHECK_THROWS_WITH_AS(parse_z2m_devices("z", R"([{"type":"Router"}])"),
                       "device [0] has no \"friendly_name\"", DiscoveryError);
  // A removed device (empty payload) is no error.
  CHECK(parse_ha_config("light", "x", "").name.empty());
}

TEST_CASE("Zigbee2MQTT: rooms from the friendly name or the description; sensors left out") {
  std::vector<Device> ds = parse_z2m_devices("zigbee2mqtt", R"([
    {"friendly_name": "Coordinator", "type": "Coordinator"},
    {"friendly_name": "upstairs/Reading Lamp", "type": "Router", "definition": {"exposes": [
        {"type": "light", "features": [{"name": "state"}, {"name": "brightness", "value_max": 254},
                                       {"name": "color_temp"}]}]}},
    {"friendly_name": "plug_1", "description": "Room: Garage", "type": "Router",
     "definition": {"exposes": [{"type": "switch", "features": [{"name": "state"}]}]}},
    {"friendly_name": "door", "type": "EndDevice",
     "definition": {"exposes": [{"type": "binary", "name": "contact"}]}}])");
  REQUIRE(ds.size() == 2);
  CHECK(ds[0].name == "reading lamp");
  CHECK(ds[0].room == "upstairs");
  CHECK(ds[0].dimmable);
  CHECK(ds[0].color_temp);
  CHECK(ds[0].protocol.command_topic == "zigbee2mqtt/upstairs/Reading Lamp/set");
  CHECK(ds[1].name == "plug 1");
  CHECK(ds[1].room == "garage");
  CHECK(ds[1].type == DeviceType::kSwitch);
  auto messages = command_messages(ds[0], DeviceCommand{{}, 50, {}, {}});
  REQUIRE(messages.size() == 1);
  CHECK(messages[0].second == R"({"brightness":127})");
  DeviceState s;
  CHECK(apply_state(ds[0], "zigbee2mqtt/upstairs/Reading Lamp",
                    R"({"state":"ON","brightness":254})", &s));
  CHECK(s.brightness_pct == 100);
  CHECK(s.reports == 1);
  CHECK_FALSE(apply_state(ds[0], "zigbee2mqtt/upstairs/Reading Lamp", "[]", &s));
  CHECK(s.reports == 1);
}

TEST_CASE("Zigbee2MQTT thermostats: a valve's set point, the room's temperature, heat and off") {
  std::vector<Device> ds = parse_z2m_devices("z", R"([
    {"friendly_name": "bedroom/radiator", "type": "EndDevice", "definition": {"exposes": [
        {"type": "climate", "features": [
            {"name": "current_heating_setpoint", "value_min": 7, "value_max": 28, "value_step": 0.5},
            {"name": "local_temperature"},
            {"name": "system_mode", "values": ["off", "auto", "heat"]}]}]}},
    {"friendly_name": "hall/valve", "type": "EndDevice", "definition": {"exposes": [
        {"type": "climate", "features": [{"name": "current_heating_setpoint"}]}]}},
    {"friendly_name": "attic/display", "type": "EndDevice", "definition": {"exposes": [
        {"type": "climate", "features": [{"name": "local_temperature"}]}]}},
    {"friendly_name": "study/trv", "type": "EndDevice", "definition": {"exposes": [
        {"type": "climate", "features": [
            {"name": "current_heating_setpoint", "value_min": 4, "value_max": 35},
            {"name": "occupied_heating_setpoint", "value_min": 6, "value_max": "hot"}]}]}}])");
  REQUIRE(ds.size() == 3);  // the display sets nothing
  // Both set points: the occupied one, with its own range (a bound that is no number: the
  // default).
  CHECK(ds[2].protocol.setpoint_property == "occupied_heating_setpoint");
  CHECK(ds[2].protocol.min_c == 6.0);
  CHECK(ds[2].protocol.max_c == 30.0);
  const Device& radiator = ds[0];
  CHECK(radiator.type == DeviceType::kThermostat);
  CHECK(radiator.room == "bedroom");
  CHECK(radiator.protocol.setpoint_property == "current_heating_setpoint");
  CHECK(radiator.protocol.heat_mode == "heat");
  CHECK(radiator.protocol.min_c == 7.0);
  CHECK(radiator.protocol.max_c == 28.0);
  auto messages = command_messages(radiator, DeviceCommand{true, {}, {}, 21.5});
  REQUIRE(messages.size() == 1);
  CHECK(messages[0].first == "z/bedroom/radiator/set");
  CHECK(messages[0].second == R"({"current_heating_setpoint":21.5,"system_mode":"heat"})");
  DeviceState s;
  CHECK(apply_state(radiator, "z/bedroom/radiator",
                    R"({"current_heating_setpoint":21.5,"local_temperature":18.2,"system_mode":"auto"})",
                    &s));
  CHECK(s.target_c == 21.5);
  CHECK(s.current_c == 18.2);
  CHECK(s.on == true);  // auto heats too
  CHECK(state_matches(s, DeviceCommand{true, {}, {}, 21.5}));
  CHECK(state_matches(s, DeviceCommand{{}, {}, {}, 21.3}));  // rounded to the valve's step
  CHECK_FALSE(state_matches(s, DeviceCommand{{}, {}, {}, 23.0}));
  // A valve without modes cannot be switched off: "on" is not sent, the set point is.
  CHECK(ds[1].protocol.heat_mode.empty());
  messages = command_messages(ds[1], DeviceCommand{false, {}, {}, 19.0});
  REQUIRE(messages.size() == 1);
  CHECK(messages[0].second == R"({"current_heating_setpoint":19.0})");
}

TEST_CASE("Home Assistant climate: mode and set point on their own topics, plain payloads") {
  std::string component, object;
  REQUIRE(parse_ha_config_topic("homeassistant", "homeassistant/climate/lr/config", &component,
                                &object));
  Device d = parse_ha_config("climate", "lr", R"({"name": "Living room heating", "~": "hvac/lr",
      "mode_cmd_t": "~/mode/set", "mode_stat_t": "~/mode", "modes": ["off", "heat"],
      "temp_cmd_t": "~/target/set", "temp_stat_t": "~/target", "curr_temp_t": "~/current",
      "min_temp": 10, "max_temp": 26, "device": {"suggested_area": "Living Room"}})");
  CHECK(d.type == DeviceType::kThermostat);
  CHECK(d.name == "living room heating");
  CHECK(d.room == "living room");
  CHECK(d.protocol.max_c == 26.0);
  auto messages = command_messages(d, DeviceCommand{true, {}, {}, 20.5});
  REQUIRE(messages.size() == 2);
  CHECK(messages[0] == std::pair<std::string, std::string>{"hvac/lr/mode/set", "heat"});
  CHECK(messages[1] == std::pair<std::string, std::string>{"hvac/lr/target/set", "20.5"});
  DeviceState s;
  CHECK(apply_state(d, "hvac/lr/target", "20.5", &s));
  CHECK(apply_state(d, "hvac/lr/current", "19", &s));
  CHECK(apply_state(d, "hvac/lr/mode", "off", &s));
  CHECK(s.target_c == 20.5);
  CHECK(s.current_c == 19.0);
  CHECK(s.on == false);
  // A temperature that is not a number changes nothing.
  CHECK_FALSE(apply_state(d, "hvac/lr/target", "warm", &s));
  CHECK(s.target_c == 20.5);
  CHECK(s.reports == 3);
  // What is wrong is named.
  CHECK_THROWS_WITH_AS(parse_ha_config("climate", "x", R"({"name": "t", "mode_cmd_t": "m"})"),
                       "\"temperature_command_topic\" is missing", DiscoveryError);
  CHECK_THROWS_WITH_AS(
      parse_ha_config("climate", "x", R"({"temp_cmd_t": "t", "min_temp": 30, "max_temp": 10})"),
      "\"min_temp\" must be below \"max_temp\"", DiscoveryError);
  CHECK_THROWS_WITH_AS(parse_ha_config("climate", "x", R"({"temp_cmd_t": "t", "max_temp": "hot"})"),
                       "\"max_temp\" must be a number, got \"hot\"", DiscoveryError);
  CHECK(celsius_text(21.0) == "21");
  CHECK(celsius_text(-0.5) == "-0.5");
}

}  // namespace
}  // namespace marvin::home
