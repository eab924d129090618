// Discovery payloads and state reports, parsed without a broker.
#include <doctest/doctest.h>

#include "home/discovery.h"

namespace marvin::home {
namespace {

TEST_CASE("discovery topics: light, switch and fan configs, with or without a node id") {
  std::string component, object;
  CHECK(parse_ha_config_topic("homeassistant", "homeassistant/light/desk/config", &component, &object));
  CHECK(component == "light");
  CHECK(object == "desk");
  CHECK(parse_ha_config_topic("homeassistant", "homeassistant/fan/n1/ceiling/config", &component, &object));
  CHECK(object == "n1/ceiling");
  CHECK_FALSE(parse_ha_config_topic("homeassistant", "homeassistant/sensor/t/config", &component, &object));
  CHECK_FALSE(parse_ha_config_topic("homeassistant", "homeassistant/light/desk/state", &component, &object));
  CHECK_FALSE(parse_ha_config_topic("homeassistant", "other/light/desk/config", &component, &object));
}

TEST_CASE("a default-schema light: brightness on its own topics, scaled") {
  Device d = parse_ha_config("light", "kitchen", R"({"name": "Kitchen_Ceiling",
      "command_topic": "k/set", "state_topic": "k/state", "brightness_command_topic": "k/b/set",
      "brightness_state_topic": "k/b", "brightness_scale": 100,
      "availability": [{"topic": "k/avail"}]})");
  CHECK(d.name == "kitchen ceiling");
  CHECK(d.dimmable);
  CHECK(d.protocol.availability_topic == "k/avail");
  auto messages = command_messages(d, DeviceCommand{true, 40, {}});
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
  CHECK_THROWS_WITH_AS(parse_ha_config("light", "x", R"({"command_topic":"c","brightness_scale":0})"),
                       "\"brightness_scale\" must be a positive integer", DiscoveryError);
  CHECK_THROWS_WITH_AS(parse_z2m_devices("z", R"({"a":1})"),
                       "the device list must be a JSON array", DiscoveryError);
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
  auto messages = command_messages(ds[0], DeviceCommand{{}, 50, {}});
  REQUIRE(messages.size() == 1);
  CHECK(messages[0].second == R"({"brightness":127})");
  DeviceState s;
  CHECK(apply_state(ds[0], "zigbee2mqtt/upstairs/Reading Lamp", R"({"state":"ON","brightness":254})", &s));
  CHECK(s.brightness_pct == 100);
  CHECK(s.reports == 1);
  CHECK_FALSE(apply_state(ds[0], "zigbee2mqtt/upstairs/Reading Lamp", "[]", &s));
  CHECK(s.reports == 1);
}

}  // namespace
}  // namespace marvin::home
